// The Strecha ground-truth camera reader (eval/ground_truth.cc): one NAME.camera file.
#include "fuzz_support.h"
#include "varsfm/eval/ground_truth.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = varsfm::fuzz::ScratchDir() / "0000.jpg.camera";
  varsfm::fuzz::WriteBytes(file, data, size);
  try {
    varsfm::ReadStrechaCamera(file);
  } catch (const varsfm::Error&) {
  }
  return 0;
}
