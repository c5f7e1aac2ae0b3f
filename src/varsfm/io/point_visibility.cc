#include "varsfm/io/point_visibility.h"

#include <unistd.h>

#include <cstdint>
#include <fstream>

#include <fmt/format.h>

#include "varsfm/util/error.h"

namespace varsfm {
namespace fs = std::filesystem;
namespace {

template <typename T>
void Put(std::ofstream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
T Get(std::ifstream& in, const fs::path& file) {
  T value;
  if (!in.read(reinterpret_cast<char*>(&value), sizeof(T))) Fail("{}: truncated", file.string());
  return value;
}

}  // namespace

void WritePointVisibility(const fs::path& file, const PointVisibility& visibility) {
  const fs::path tmp =
      file.parent_path() / fmt::format(".{}.tmp-{}", file.filename().string(), ::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) Fail("{}: cannot open for writing", file.string());
    Put<uint64_t>(out, visibility.size());
    for (const auto& ids : visibility) {
      Put<uint32_t>(out, static_cast<uint32_t>(ids.size()));
      for (image_t id : ids) Put<uint32_t>(out, static_cast<uint32_t>(id));
    }
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      Fail("{}: write failed (disk full?)", file.string());
    }
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    Fail("{}: cannot write: {}", file.string(), ec.message());
  }
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
