// The textured OBJ reader (io/obj_io.cc): an input is the OBJ and its MTL, cut at
// kPartSeparator. The seeds name the material file model.mtl and the atlas page page.png, which
// is written once, so mutations reach the faces and materials rather than failing to open files.
#include <opencv2/core.hpp>

#include "fuzz_support.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/obj_io.h"
#include "varsfm/util/error.h"

namespace {

const std::filesystem::path& ModelDir() {
  static const std::filesystem::path dir = [] {
    const auto d = varsfm::fuzz::ScratchDir() / "obj";
    std::filesystem::create_directories(d);
    varsfm::WriteImage(d / "page.png", cv::Mat(4, 4, CV_8UC3, cv::Scalar(40, 80, 120)));
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto parts = varsfm::fuzz::SplitParts(data, size, 2);
  varsfm::fuzz::WriteBytes(ModelDir() / "model.obj", parts[0].data(), parts[0].size());
  varsfm::fuzz::WriteBytes(ModelDir() / "model.mtl", parts[1].data(), parts[1].size());
  try {
    varsfm::ReadTexturedObj(ModelDir() / "model.obj");
  } catch (const varsfm::Error&) {
  }
  return 0;
}
