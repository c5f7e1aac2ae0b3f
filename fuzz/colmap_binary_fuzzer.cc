// The COLMAP binary model reader (io/colmap_model.cc): an input is cameras.bin, images.bin
// and points3D.bin, cut at kPartSeparator, read back as the model folder they make.
#include "fuzz_support.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    varsfm::ReadColmapModel(varsfm::fuzz::WriteParts(
        data, size, "colmap_binary", {"cameras.bin", "images.bin", "points3D.bin"}));
  } catch (const varsfm::Error&) {
  }
  return 0;
}
