#pragma once
// Where a video's keyframes go in a workspace: a folder per video under the workspace's frames
// folder, named after the video, so that two videos extracted into one workspace keep their own
// frames (each numbers its keyframes frame_NNNNNN.jpg) and image names that say which video
// they come from (e.g. "walk/frame_000120.jpg").
#include <filesystem>

#include "varsfm/image/video_keyframes.h"

namespace varsfm {

// The folder the image names of video keyframes are relative to: <workspace dir>/<workspace
// stem>_frames.
std::filesystem::path VideoFramesDir(const std::filesystem::path& workspace);

// The name of the folder under VideoFramesDir(workspace) that holds, or would hold, the keyframes
// of `video` (as ExtractVideoFrames chooses it below). Throws varsfm::Error when the video does not
// exist or cannot be read.
std::string VideoFramesFolderName(const std::filesystem::path& workspace,
                                  const std::filesystem::path& video);

// Writes the keyframes of `video` into its folder under VideoFramesDir(workspace) and returns
// their names relative to VideoFramesDir(workspace). The folder is the video's file stem, or
// stem_2, stem_3, ... when a folder of that name holds another video's frames; a video is
// recognised by its size and the bytes at its start and end (recorded in the folder's
// video.txt), so extracting the same video again reuses its folder and names (a resume). A
// folder made for a video that cannot be decoded is removed again.
KeyframeSummary ExtractVideoFrames(const std::filesystem::path& workspace,
                                   const std::filesystem::path& video,
                                   const KeyframeOptions& options);

}  // namespace varsfm
