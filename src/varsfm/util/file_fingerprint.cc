#include "varsfm/util/file_fingerprint.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>

#include <fmt/format.h>

#include "varsfm/util/error.h"
#include "varsfm/util/fnv1a.h"

namespace varsfm {
namespace {

constexpr std::streamoff kFingerprintBytes = 1 << 16;  // hashed at each end of the file

}  // namespace

std::string FileFingerprint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) Fail("cannot read {}", file.string());
  const std::streamoff size = in.tellg();
  std::array<char, kFingerprintBytes> buffer;
  uint64_t hash = kFnv1aOffsetBasis;
  for (const std::streamoff start :
       {std::streamoff{0}, std::max<std::streamoff>(0, size - kFingerprintBytes)}) {
    in.seekg(start);
    in.read(buffer.data(), kFingerprintBytes);
    hash = Fnv1a(buffer.data(), static_cast<size_t>(in.gcount()), hash);
    in.clear();
  }
  return fmt::format("{} bytes, fnv1a {:016x}", size, hash);
}

}  // namespace varsfm
