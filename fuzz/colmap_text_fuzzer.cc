// The COLMAP text model reader (io/colmap_model.cc): an input is cameras.txt, images.txt
// and points3D.txt, cut at kPartSeparator, read back as the model folder they make.
#include "fuzz_support.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    varsfm::ReadColmapModel(varsfm::fuzz::WriteParts(
        data, size, "colmap_text", {"cameras.txt", "images.txt", "points3D.txt"}));
  } catch (const varsfm::Error&) {
  }
  return 0;
}
