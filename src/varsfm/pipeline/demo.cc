#include "varsfm/pipeline/demo.h"

#include "varsfm/eval/ground_truth.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/timer.h"

namespace varsfm {

void DemoOptions::Check() const {
  scene.Check();
  // The evaluation's similarity alignment needs three registered images.
  CheckInRange("--images", scene.num_images, 3, 200);
  run.Check();
}

DemoSummary RunDemo(const DemoOptions& options) {
  options.Check();
  const auto image_dir = options.output / "images";
  const auto gt_dir = options.output / "gt";
  Timer timer;
  if (!std::filesystem::exists(image_dir)) {
    info("demo: rendering {} images of a synthetic scene (zoom x{:.1f}) into {}",
         options.scene.num_images, options.scene.zoom, image_dir.string());
    WriteRenderedScene(RenderSyntheticScene(options.scene, OptionsCheck::kDoneByCaller), image_dir,
                       gt_dir);
    info("demo: rendered in {:.1f} s", timer.Seconds());
  }
  RunOptions run = options.run;
  run.input = image_dir;
  run.output = options.output;
  DemoSummary result;
  result.run = RunAll(run, OptionsCheck::kDoneByCaller);
  result.evaluation =
      EvaluateAgainstGroundTruth(result.run.map.reconstruction, ReadStrechaGroundTruth(gt_dir));
  WriteJsonAtomically(options.output / "evaluation.json", ToJson(result.evaluation));
  fmt::print("{}", FormatReport(result.evaluation));
  return result;
}

}  // namespace varsfm
