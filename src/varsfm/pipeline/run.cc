#include "varsfm/pipeline/run.h"

#include <fstream>

#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/timer.h"

namespace varsfm {

RunResult RunAll(const RunOptions& options) {
  namespace fs = std::filesystem;
  if (!fs::exists(options.input)) Fail("input {} does not exist", options.input.string());
  const bool video = fs::is_regular_file(options.input);
  if (options.output.empty()) Fail("no output folder given");
  if (fs::exists(options.output) && !fs::is_directory(options.output))
    Fail("output {} exists and is not a folder", options.output.string());
  fs::create_directories(options.output);
  const fs::path workspace = options.output / "workspace.db";

  RunResult result;
  Timer timer;
  ExtractOptions extract = options.extract;
  extract.workspace = workspace;
  extract.image_dir.clear();
  extract.video.clear();
  (video ? extract.video : extract.image_dir) = options.input;
  const ExtractSummary extracted = RunExtraction(extract);
  result.seconds_extract = timer.Seconds();

  timer.Restart();
  MatchOptions match = options.match;
  match.workspace = workspace;
  const size_t num_images = extracted.num_existing + extracted.num_extracted;
  match.strategy = options.matching;
  if (match.strategy == "auto")
    match.strategy = (video || num_images > 40) ? "sequential" : "exhaustive";
  RunMatching(match);
  result.seconds_match = timer.Seconds();

  timer.Restart();
  MapOptions map = options.map;
  map.workspace = workspace;
  map.output = options.output;
  map.image_dir = extracted.image_dir;
  if (video) map.mapper.sequential_order = true;
  result.map = RunMapping(map);
  result.seconds_map = timer.Seconds();

  // Add the earlier stages' times to the summary written by the mapping stage.
  const fs::path summary_path = options.output / "summary.json";
  nlohmann::json summary = nlohmann::json::parse(std::ifstream(summary_path));
  summary["seconds"]["extract"] = result.seconds_extract;
  summary["seconds"]["match"] = result.seconds_match;
  summary["seconds"]["map"] = result.seconds_map;
  summary["matching_strategy"] = match.strategy;
  std::ofstream(summary_path) << summary.dump(2) << "\n";

  info("run: wrote {}/sparse (COLMAP text + binary), sparse.ply, bundle.out, summary.json",
       options.output.string());
  return result;
}

}  // namespace varsfm
