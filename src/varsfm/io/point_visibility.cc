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
T Get(std::istream& in, const fs::path& file) {
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

PointVisibilityReader::PointVisibilityReader(const fs::path& file)
    : file_(file), in_(file, std::ios::binary) {
  if (!in_) Fail("{}: cannot open", file.string());
  std::error_code ec;
  bytes_ = fs::file_size(file, ec);
  if (ec) Fail("{}: cannot read its size", file.string());
  const uint64_t n = Get<uint64_t>(in_, file);
  // Each point takes at least its 4-byte count: a larger count is a damaged file, not a reason
  // to allocate.
  if (n > (bytes_ - sizeof(uint64_t)) / sizeof(uint32_t))
    Fail("{}: {} points do not fit in {} bytes", file.string(), n, bytes_);
  count_ = static_cast<size_t>(n);
}

void PointVisibilityReader::Next(std::vector<image_t>* ids) {
  if (next_++ >= count_) Fail("{}: read past its {} points", file_.string(), count_);
  const uint32_t count = Get<uint32_t>(in_, file_);
  if (count > bytes_ / sizeof(uint32_t))
    Fail("{}: a point seen by {} images does not fit in {} bytes", file_.string(), count, bytes_);
  // The ids in one read: one by one through the stream they were most of the reading.
  bytes_read_.resize(size_t{count} * sizeof(uint32_t));
  if (!in_.read(bytes_read_.data(), static_cast<std::streamsize>(bytes_read_.size())))
    Fail("{}: truncated", file_.string());
  ids->resize(count);
  for (uint32_t j = 0; j < count; ++j)
    (*ids)[j] = GetLittleEndian<uint32_t>(bytes_read_.data() + j * sizeof(uint32_t));
}

void PointVisibilityReader::ExpectEnd() {
  if (next_ != count_) Fail("{}: {} of its {} points read", file_.string(), next_, count_);
  if (in_.peek() != std::ifstream::traits_type::eof())
    Fail("{}: bytes after the last point", file_.string());
}

PointVisibility ReadPointVisibility(const fs::path& file) {
  PointVisibilityReader reader(file);
  PointVisibility visibility(reader.size());
  for (auto& ids : visibility) reader.Next(&ids);
  reader.ExpectEnd();
  return visibility;
}

}  // namespace varsfm
