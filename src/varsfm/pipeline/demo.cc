#include "varsfm/pipeline/demo.h"

#include "varsfm/eval/ground_truth.h"
#include "varsfm/io/database.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/path_lock.h"
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
  OutputFolderLock output_lock(options.output);
  // The scene is rendered into the output folder, so the folder is checked before, as `run`
  // would check it (output_folder.h): not a folder of other files, nor another run's.
  CheckOutputFolderIsOurs(options.output);
  if (!std::filesystem::exists(image_dir)) {
    if (std::filesystem::exists(options.output / "workspace.db"))
      Fail("output folder {} holds another run's workspace: give a new or empty folder",
           options.output.string());
    output_lock.CreateAndLock();
    Database(options.output / "workspace.db");  // marks the folder as varsfm's for `run`
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
