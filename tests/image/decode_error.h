#pragma once
// The message of a decoding failure, for the tests of each decoder's bad input.
#include <cstdint>
#include <string>
#include <vector>

#include "varsfm/image/image_file.h"
#include "varsfm/util/error.h"

namespace varsfm::testing {

// The error DecodeImage gives for file `name` of `bytes`; empty when they decode.
inline std::string DecodeErrorOf(const std::string& name, const std::vector<uint8_t>& bytes) {
  try {
    DecodeImage(name, bytes, ColorMode::kColor);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace varsfm::testing
