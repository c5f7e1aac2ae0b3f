#pragma once
// zlib compression (RFC 1950), the format browsers inflate with DecompressionStream("deflate"):
// the report compresses the embedded model this way.
#include <cstdint>
#include <vector>

namespace varsfm {

// Throws varsfm::Error when zlib fails (out of memory).
std::vector<uint8_t> Deflate(const std::vector<uint8_t>& bytes);

}  // namespace varsfm
