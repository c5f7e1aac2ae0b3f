#include "varsfm/image/scratch_image.h"

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "varsfm/util/scratch_memory.h"

namespace varsfm {
namespace {

// OpenCV's allocator interface (as its StdMatAllocator) over scratch memory in one folder: each
// buffer its own ScratchMemory, kept alive by the UMatData's userdata.
class ScratchMatAllocator final : public cv::MatAllocator {
 public:
  explicit ScratchMatAllocator(std::filesystem::path folder) : folder_(std::move(folder)) {}

  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step,
                         cv::AccessFlag, cv::UMatUsageFlags) const override {
    size_t total = CV_ELEM_SIZE(type);
    for (int i = dims - 1; i >= 0; --i) {
      if (step) {
        if (data && step[i] != cv::Mat::AUTO_STEP)
          total = step[i];
        else
          step[i] = total;
      }
      total *= sizes[i];
    }
    auto* u = new cv::UMatData(this);
    if (data) {
      u->data = u->origdata = static_cast<uchar*>(data);
      u->flags |= cv::UMatData::USER_ALLOCATED;
    } else {
      auto* memory = new std::shared_ptr<ScratchMemory>(ScratchMemory::Create(folder_, total));
      u->userdata = memory;
      u->data = u->origdata = static_cast<uchar*>((*memory)->data());
    }
    u->size = total;
    return u;
  }

  bool allocate(cv::UMatData* u, cv::AccessFlag, cv::UMatUsageFlags) const override {
    return u != nullptr;
  }

  void deallocate(cv::UMatData* u) const override {
    if (!u) return;
    delete static_cast<std::shared_ptr<ScratchMemory>*>(u->userdata);
    delete u;
  }

 private:
  std::filesystem::path folder_;
};

// One allocator per folder for the process's lifetime: a Mat calls its allocator when its last
// copy goes, whenever that is. Never destroyed (no order to keep at exit).
const cv::MatAllocator* AllocatorFor(const std::filesystem::path& folder) {
  static std::mutex mutex;
  static auto* allocators = new std::map<std::string, std::unique_ptr<ScratchMatAllocator>>();
  const std::lock_guard lock(mutex);
  std::unique_ptr<ScratchMatAllocator>& slot = (*allocators)[folder.string()];
  if (!slot) slot = std::make_unique<ScratchMatAllocator>(folder);
  return slot.get();
}

}  // namespace

cv::Mat CopyToScratch(const cv::Mat& image, const std::filesystem::path& folder) {
  cv::Mat copy;
  copy.allocator = const_cast<cv::MatAllocator*>(AllocatorFor(folder));
  image.copyTo(copy);
  return copy;
}

}  // namespace varsfm
