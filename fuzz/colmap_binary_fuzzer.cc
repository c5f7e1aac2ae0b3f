// The COLMAP binary model reader (io/colmap_model.cc): an input is cameras.bin, images.bin
// and points3D.bin, cut at kPartSeparator, read back as the model folder they make.
#include "fuzz_support.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = varsfm::fuzz::ScratchDir() / "colmap_binary";
    std::filesystem::create_directories(d);
    return d;
  }();
  const auto parts = varsfm::fuzz::SplitParts(data, size, 3);
  const char* names[] = {"cameras.bin", "images.bin", "points3D.bin"};
  for (int i = 0; i < 3; ++i)
    varsfm::fuzz::WriteBytes(dir / names[i], parts[i].data(), parts[i].size());
  try {
    varsfm::ReadColmapModel(dir);
  } catch (const varsfm::Error&) {
  }
  return 0;
}
