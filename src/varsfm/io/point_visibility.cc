#include "varsfm/io/point_visibility.h"

#include <cstdint>
#include <fstream>

#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"

namespace varsfm {
namespace fs = std::filesystem;
namespace {

template <typename T>
T Get(std::ifstream& in, const fs::path& file) {
  char bytes[sizeof(T)];
  if (!in.read(bytes, sizeof(T))) Fail("{}: truncated", file.string());
  return GetLittleEndian<T>(bytes);
}

}  // namespace

void WritePointVisibility(const fs::path& file, const PointVisibility& visibility) {
  WriteFileAtomically(file, [&](std::ostream& out) {
    PutLittleEndian<uint64_t>(out, visibility.size());
    for (const auto& ids : visibility) {
      PutLittleEndian<uint32_t>(out, static_cast<uint32_t>(ids.size()));
      for (image_t id : ids) PutLittleEndian<uint32_t>(out, static_cast<uint32_t>(id));
    }
  });
}

PointVisibility ReadPointVisibility(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) Fail("{}: cannot open", file.string());
  std::error_code ec;
  const uintmax_t size = fs::file_size(file, ec);
  if (ec) Fail("{}: cannot read its size", file.string());
  const uint64_t n = Get<uint64_t>(in, file);
  // Each point takes at least its 4-byte count: a larger count is a damaged file, not a reason
  // to allocate.
  if (n > (size - sizeof(uint64_t)) / sizeof(uint32_t))
    Fail("{}: {} points do not fit in {} bytes", file.string(), n, size);
  PointVisibility visibility(n);
  for (auto& ids : visibility) {
    const uint32_t count = Get<uint32_t>(in, file);
    if (count > size / sizeof(uint32_t))
      Fail("{}: a point seen by {} images does not fit in {} bytes", file.string(), count, size);
    ids.resize(count);
    for (image_t& id : ids) id = Get<uint32_t>(in, file);
  }
  if (in.peek() != std::ifstream::traits_type::eof())
    Fail("{}: bytes after the last point", file.string());
  return visibility;
}

}  // namespace varsfm
