#pragma once
// Which cameras of an adjustment take their shared intrinsics (IntrinsicsOptions::
// shared_per_size) from one block: the groups are per image size and, within a size, per zoom
// band. A zoom moves the principal point (a centred crop scales its offset from the image centre
// with the focal length), so zoomed and unzoomed photos of one size do not share it
// (docs/measurements.md, "The principal point under zoom").
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/util/types.h"

namespace varsfm {

// A shared block's key: image width, height and zoom band.
using IntrinsicsGroupKey = std::tuple<int, int, int>;

// Bit i set: parameter i is shared per image size (IntrinsicsOptions::shared_per_size).
unsigned SharedIntrinsicsMask(const IntrinsicsOptions& options);

// The zoom bands of one size's cameras, `by_focal` (focal length, id; ascending): the group each
// joins, an index into by_focal's bands, or none (empty) when the size's images are fewer than
// `min_images`. Sorted by focal length, a band takes cameras up to `max_ratio` times its
// shortest one (0: one band) and the next band starts at the first it leaves out. A band whose
// cameras `images_of_camera` counts at least min_images times is a group of its own; a smaller
// one joins the nearest such band by focal-length ratio (alone, a camera would hold what it
// cannot estimate at its starting value, and the nearest zoom is the nearest guess), and with no
// such band the size is one group.
std::vector<int> ZoomBandGroups(const std::vector<std::pair<double, camera_t>>& by_focal,
                                const std::map<camera_t, int>& images_of_camera, double max_ratio,
                                int min_images);

// The variable cameras (not in `constant_cameras`) of the problem's `images` that take
// parameters from a shared block, with its key: per image size, its zoom bands' groups. It is
// the images that pin a shared parameter down: one camera of many images (`--intrinsics shared`)
// forms a group as several cameras of one image each do. Empty when nothing is shared.
std::map<camera_t, IntrinsicsGroupKey> SharedGroupMembers(
    const IntrinsicsOptions& options, const std::set<camera_t>& constant_cameras,
    const std::set<image_t>& images, const Reconstruction& rec);

}  // namespace varsfm
