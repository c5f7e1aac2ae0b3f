#pragma once
// Images in scratch memory (util/scratch_memory.h): the photos a stage holds for every view at
// once (multi-view stereo's), with pages the kernel may write out to the scratch folder's disk
// and drop under memory pressure.
#include <filesystem>

#include <opencv2/core.hpp>

namespace varsfm {

// A copy of `image` whose pixels lie in scratch memory in `folder`; it frees that memory when the
// last Mat sharing it goes. Where the scratch memory cannot be made (a full disk), OpenCV
// allocates the copy on the heap instead (ScratchFolderUsable, util/scratch_memory.h, says so
// beforehand for a folder that cannot hold any).
cv::Mat CopyToScratch(const cv::Mat& image, const std::filesystem::path& folder);

}  // namespace varsfm
