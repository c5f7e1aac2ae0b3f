// The point-cloud PLY reader (io/ply.cc on io/ply_format.cc): ascii or binary clouds that other
// tools wrote. Only varsfm::Error may leave it; anything else (a crash, another exception, a
// leak, undefined behaviour, an allocation beyond the limit) is a finding.
#include "fuzz_support.h"
#include "varsfm/io/ply.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = varsfm::fuzz::ScratchDir() / "cloud.ply";
  varsfm::fuzz::WriteBytes(file, data, size);
  try {
    varsfm::ReadPly(file);
  } catch (const varsfm::Error&) {
  }
  return 0;
}
