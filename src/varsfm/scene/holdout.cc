#include "varsfm/scene/holdout.h"

#include <algorithm>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

void CheckHoldout(int every) {
  if (every < 0 || every == 1) {
    FailOption("--holdout", "0 (no held-out views) or an integer >= 2 (every N-th image)", every);
  }
}

std::vector<image_t> HeldOutImageIds(const Reconstruction& reconstruction, int every) {
  if (every <= 0) return {};
  std::vector<image_t> ids = reconstruction.RegisteredImageIds();
  std::sort(ids.begin(), ids.end(), [&](image_t a, image_t b) {
    return reconstruction.image(a).name < reconstruction.image(b).name;
  });
  std::vector<image_t> held_out;
  for (size_t i = 0; i < ids.size(); i += static_cast<size_t>(every)) held_out.push_back(ids[i]);
  return held_out;
}

size_t HoldOutImages(Reconstruction* reconstruction, int every) {
  const std::vector<image_t> ids = HeldOutImageIds(*reconstruction, every);
  for (const image_t id : ids) reconstruction->DeRegisterImage(id);
  return ids.size();
}

}  // namespace varsfm
