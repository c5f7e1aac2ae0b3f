#pragma once
// Base64 (RFC 4648, with padding): the report carries its binary parts (thumbnails, the glTF
// model, point coordinates) inside the HTML file, as data URIs or in script elements.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace varsfm {

std::string Base64Encode(const uint8_t* data, size_t size);
inline std::string Base64Encode(const std::vector<uint8_t>& bytes) {
  return Base64Encode(bytes.data(), bytes.size());
}

}  // namespace varsfm
