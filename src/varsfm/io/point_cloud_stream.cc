#include "varsfm/io/point_cloud_stream.h"

#include "varsfm/io/ply.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"

namespace varsfm {

PointCloudStream::PointCloudStream(const std::filesystem::path& folder) {
  records_.emplace(folder);
  visibility_.emplace(folder);
}

void PointCloudStream::Add(const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                           const Eigen::Matrix<uint8_t, 3, 1>& color,
                           const std::vector<image_t>& seen_by) {
  record_.clear();
  for (const Eigen::Vector3d* v : {&position, &normal})
    for (int k = 0; k < 3; ++k) AppendLittleEndian(&record_, static_cast<float>((*v)[k]));
  for (int k = 0; k < 3; ++k) AppendLittleEndian(&record_, color[k]);
  records_->Append(record_.data(), record_.size());
  record_.clear();
  AppendLittleEndian(&record_, static_cast<uint32_t>(seen_by.size()));
  for (image_t id : seen_by) AppendLittleEndian(&record_, static_cast<uint32_t>(id));
  visibility_->Append(record_.data(), record_.size());
  ++count_;
}

void PointCloudStream::Write(const std::filesystem::path& ply,
                             const std::filesystem::path& vis) && {
  if (!records_ || !visibility_) Fail("PointCloudStream: written already");
  WriteFileAtomically(ply, [&](std::ostream& out) {
    out << PointCloudPlyHeader(count_, /*normals=*/true, /*colors=*/true, /*visibility=*/false, 0);
    records_->CopyTo(out);
  });
  records_.reset();
  WriteFileAtomically(vis, [&](std::ostream& out) {
    PutLittleEndian<uint64_t>(out, count_);
    visibility_->CopyTo(out);
  });
  visibility_.reset();
}

}  // namespace varsfm
