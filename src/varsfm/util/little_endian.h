#pragma once
// Binary values in little-endian byte order, as PLY's binary_little_endian and COLMAP's model
// files store them, whatever the host: the bytes are reversed on a big-endian one.
#include <algorithm>
#include <bit>
#include <cstring>
#include <ostream>
#include <type_traits>

namespace varsfm {

// `value` with its bytes in the other order on a big-endian host, unchanged on a little-endian
// one; so the same call converts to and from little-endian.
template <typename T>
T SwapLittleEndian(T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  if constexpr (std::endian::native == std::endian::big) {
    auto* bytes = reinterpret_cast<char*>(&value);
    std::reverse(bytes, bytes + sizeof(T));
  }
  return value;
}

// Writes `value` as sizeof(T) little-endian bytes.
template <typename T>
void PutLittleEndian(std::ostream& out, T value) {
  value = SwapLittleEndian(value);
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

// Appends `value` as sizeof(T) little-endian bytes to a byte container (std::string,
// std::vector<uint8_t>) that is assembled before it is written.
template <typename T, typename Bytes>
void AppendLittleEndian(Bytes* bytes, T value) {
  value = SwapLittleEndian(value);
  const auto* p = reinterpret_cast<const char*>(&value);
  bytes->insert(bytes->end(), p, p + sizeof(T));
}

// The value stored as sizeof(T) little-endian bytes at `bytes`.
template <typename T>
T GetLittleEndian(const char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return SwapLittleEndian(value);
}

}  // namespace varsfm
