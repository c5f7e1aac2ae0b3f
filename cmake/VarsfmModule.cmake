# varsfm_module(NAME DEPS dep...)
# One library module per folder of src/varsfm: a static library varsfm_NAME built from every
# .cc in the folder, with src/ on the include path. Modules list the modules they use, so the
# dependency graph follows the data flow (images -> features -> matches -> model -> ...).
function(varsfm_module name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cc)
  if(sources)
    add_library(varsfm_${name} STATIC ${sources})
    target_include_directories(varsfm_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(varsfm_${name} PUBLIC ${ARG_DEPS})
    target_compile_options(varsfm_${name} PRIVATE -Wall -Wextra)
  else()
    add_library(varsfm_${name} INTERFACE)
    target_include_directories(varsfm_${name} INTERFACE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(varsfm_${name} INTERFACE ${ARG_DEPS})
  endif()
  add_library(varsfm::${name} ALIAS varsfm_${name})
endfunction()

# varsfm_test(MODULE LIBS lib...)
# One test program per tests/MODULE folder, from every *_test.cc in it, registered with ctest.
function(varsfm_test module)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc)
  if(NOT sources)
    return()
  endif()
  add_executable(${module}_test ${sources})
  target_link_libraries(${module}_test PRIVATE ${ARG_LIBS} varsfm_test_support GTest::gtest_main)
  # Reading TIFF/BMP/... and video loads the OpenCV I/O plug-in at run time.
  add_dependencies(${module}_test varsfm_opencv_io)
  gtest_discover_tests(${module}_test WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                       DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT ${VARSFM_TEST_TIMEOUT})
endfunction()
