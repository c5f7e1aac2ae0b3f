#include "varsfm/pipeline/scratch_choice.h"

#include "varsfm/camera/image_size.h"
#include "varsfm/util/log.h"
#include "varsfm/util/scratch_memory.h"
#include "varsfm/util/usable_memory.h"

namespace varsfm {

size_t ViewBytes(const Reconstruction& rec, int max_size, size_t bytes_per_pixel) {
  size_t pixels = 0;
  for (image_t id : rec.RegisteredImageIds()) {
    const ScaledSize size = SizeWithin(rec.CameraOf(id), max_size);
    pixels += static_cast<size_t>(size.width) * static_cast<size_t>(size.height);
  }
  return pixels * bytes_per_pixel;
}

std::filesystem::path ScratchFolderFor(const std::filesystem::path& output, size_t view_bytes,
                                       const char* what) {
  const size_t usable = UsableMemoryBytes();
  if (usable == 0 || view_bytes <= usable / 4) return {};
  std::filesystem::path folder = NearestExistingFolder(output);
  info("{} (~{} MB) kept in scratch memory on the disk of {} (usable memory {} MB)", what,
       view_bytes >> 20, folder.string(), usable >> 20);
  return folder;
}

}  // namespace varsfm
