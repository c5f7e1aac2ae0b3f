#include "varsfm/pipeline/match.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include "varsfm/io/database.h"
#include "varsfm/io/result_settings.h"
#include "varsfm/matching/pair_selection.h"
#include "varsfm/pipeline/retrieval_neighbors.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// Pairs are processed in chunks so that only the features of the images a chunk touches are
// held in memory (large exhaustive runs), while each chunk still has enough pairs to keep all
// cores busy.
constexpr size_t kPairsPerChunk = 256;
// A transaction holds at most this many pairs (besides the time limit, commit_interval).
constexpr size_t kPairsPerCommit = 256;

struct LoadedImage {
  FeatureKeypoints keypoints;
  std::unique_ptr<MatchableDescriptors> descriptors;
};

struct PairResult {
  FeatureMatches matches;
  TwoViewGeometry geometry;
};

// Images with both keypoints and descriptors, in name order (the sequential order).
std::vector<DbImage> ImagesWithFeatures(const Database& db) {
  std::vector<DbImage> images;
  for (DbImage& image : db.ReadAllImages()) {
    if (db.ExistsKeypoints(image.image_id) && db.ExistsDescriptors(image.image_id)) {
      images.push_back(std::move(image));
    }
  }
  std::sort(images.begin(), images.end(),
            [](const DbImage& a, const DbImage& b) { return a.name < b.name; });
  return images;
}

// Loads (serially: one database connection) and prepares (in parallel) the features of the
// images `pairs` use, dropping those no longer needed.
void LoadFeatures(const Database& db, const ImagePairs& pairs, bool use_simd,
                  std::map<image_t, std::shared_ptr<LoadedImage>>* cache) {
  std::set<image_t> needed;
  for (const auto& [id1, id2] : pairs) needed.insert({id1, id2});
  std::erase_if(*cache, [&](const auto& entry) { return !needed.contains(entry.first); });
  std::vector<std::pair<image_t, FeatureDescriptors>> to_prepare;
  for (image_t id : needed) {
    if (cache->contains(id)) continue;
    auto features = std::make_shared<LoadedImage>();
    features->keypoints = db.ReadKeypoints(id);
    FeatureDescriptors descriptors = db.ReadDescriptors(id);
    if (static_cast<size_t>(descriptors.rows()) != features->keypoints.size()) {
      Fail("image {} has {} keypoints but {} descriptors in the workspace", id,
           features->keypoints.size(), descriptors.rows());
    }
    (*cache)[id] = std::move(features);
    to_prepare.emplace_back(id, std::move(descriptors));
  }
  tbb::parallel_for(size_t{0}, to_prepare.size(), [&](size_t k) {
    (*cache)[to_prepare[k].first]->descriptors =
        std::make_unique<MatchableDescriptors>(to_prepare[k].second, use_simd);
  });
}

PairResult MatchPair(const LoadedImage& f1, const LoadedImage& f2, image_t id1, image_t id2,
                     const MatchOptions& options) {
  PairResult result;
  result.matches = MatchDescriptors(*f1.descriptors, *f2.descriptors, options.matching);
  VerificationOptions verification = options.verification;
  // Seeded by the pair, not by its position in the run: re-runs and thread counts agree.
  verification.seed = DeriveSeed(options.seed, Database::ImagePairToPairId(id1, id2));
  result.geometry = VerifyTwoViewGeometry(f1.keypoints, f2.keypoints, result.matches, verification);
  // As COLMAP: a pair without enough support keeps its raw matches and gets an empty geometry.
  if (result.geometry.inlier_matches.size() <
      static_cast<size_t>(options.verification.min_num_inliers)) {
    result.geometry = TwoViewGeometry();
  }
  return result;
}

// The settings that change a pair's matches and geometry, in a canonical text (sorted keys): a
// re-run with other ones matches the pair again. Left out on purpose: the strategy and overlap
// (they choose pairs, not what a pair gives), threads and use_simd (same results).
std::string MatchSettings(const MatchOptions& options) {
  nlohmann::json settings;
  settings["max_ratio"] = options.matching.max_ratio;
  settings["max_distance"] = options.matching.max_distance;
  settings["cross_check"] = options.matching.cross_check;
  const VerificationOptions& verification = options.verification;
  // By name: pairs a workspace recorded as verified by another estimator, or by an estimator
  // recorded by its number as earlier versions did, are verified again.
  settings["method"] = NameOf(kRansacMethodNames, verification.method);
  settings["max_error"] = verification.max_error;
  settings["homography_max_error"] = verification.homography_max_error;
  settings["min_num_inliers"] = verification.min_num_inliers;
  settings["confidence"] = verification.confidence;
  settings["max_num_trials"] = verification.max_num_trials;
  settings["max_H_inlier_ratio"] = verification.max_H_inlier_ratio;
  if (verification.method == RansacMethod::kGraphCut) {  // the only method they change
    settings["mean_neighbours"] = verification.mean_neighbours;
    settings["spatial_coherence"] = verification.spatial_coherence;
  }
  settings["degeneracy_recovery"] = verification.degeneracy_recovery;
  settings["seed"] = options.seed;  // verification.seed is derived from it per pair
  return settings.dump();
}

// The selected pairs still to match: pairs matched with these settings are skipped (counted in
// summary.num_skipped); those matched with other settings are matched again, failed ones
// included. A pair with no record (matched by COLMAP or an earlier varsfm) is kept and recorded
// as matched with these settings.
ImagePairs PairsToMatch(Database& db, ResultSettings& record, int64_t settings,
                        const ImagePairs& selected, MatchSummary& summary) {
  const std::unordered_map<image_pair_t, int64_t> recorded = record.ReadPairSettings();
  ImagePairs pairs, unrecorded;
  size_t num_stale = 0;
  for (const auto& [id1, id2] : selected) {
    if (db.ExistsTwoViewGeometry(id1, id2)) {
      const auto it = recorded.find(Database::ImagePairToPairId(id1, id2));
      if (it == recorded.end()) unrecorded.emplace_back(id1, id2);
      if (it == recorded.end() || it->second == settings) {
        ++summary.num_skipped;
        continue;
      }
      ++num_stale;
    }
    pairs.emplace_back(id1, id2);
  }
  if (!unrecorded.empty()) {
    Database::Transaction transaction(db);
    for (const auto& [id1, id2] : unrecorded) record.WritePairSettings(id1, id2, settings);
    transaction.Commit();
    info("match: {} pairs matched with unrecorded settings (COLMAP's or an earlier varsfm's): kept",
         unrecorded.size());
  }
  if (num_stale > 0) info("match: {} pairs were matched with other settings: again", num_stale);
  return pairs;
}

// Writes pairs as they are verified, each whole, committing every commit_interval seconds: a
// kill loses at most that much work, while one commit per pair would cost a commit per pair
// (0.25 ms each, measured, in WAL mode).
class PairWriter {
 public:
  PairWriter(Database& db, ResultSettings& record, int64_t settings, const MatchOptions& options,
             MatchSummary& summary)
      : db_(db),
        record_(record),
        settings_(settings),
        options_(options),
        summary_(summary),
        last_commit_(Now()) {}

  // The open transaction rolls back when the writer is destroyed by an error.
  ~PairWriter() = default;

  void Write(image_t id1, image_t id2, const PairResult& result) {
    if (!transaction_) transaction_.emplace(db_);
    db_.WriteMatches(id1, id2, result.matches);
    db_.WriteTwoViewGeometry(id1, id2, result.geometry);
    record_.WritePairSettings(id1, id2, settings_);
    if (!result.geometry.inlier_matches.empty()) {
      ++summary_.num_verified;
      summary_.num_inlier_matches += result.geometry.inlier_matches.size();
    }
    ++in_transaction_;
    const double now = Now();
    if (in_transaction_ >= kPairsPerCommit || now - last_commit_ >= options_.commit_interval) {
      Commit(now);
    }
  }

  void Finish() { Commit(Now()); }

 private:
  double Now() const {
    if (options_.clock) return options_.clock();
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  void Commit(double now) {
    if (transaction_) transaction_->Commit();
    transaction_.reset();
    in_transaction_ = 0;
    last_commit_ = now;
  }

  Database& db_;
  ResultSettings& record_;
  const int64_t settings_;
  const MatchOptions& options_;
  MatchSummary& summary_;
  std::optional<Database::Transaction> transaction_;
  size_t in_transaction_ = 0;
  double last_commit_;
};

// Verifies `pairs` in parallel, written in order as they finish.
void MatchPairs(Database& db, ResultSettings& record, int64_t settings, const ImagePairs& pairs,
                const MatchOptions& options, MatchSummary& summary) {
  Progress progress("match", pairs.size());
  PairWriter writer(db, record, settings, options, summary);
  std::map<image_t, std::shared_ptr<LoadedImage>> cache;
  for (size_t begin = 0; begin < pairs.size(); begin += kPairsPerChunk) {
    const size_t end = std::min(pairs.size(), begin + kPairsPerChunk);
    LoadFeatures(db, ImagePairs(pairs.begin() + begin, pairs.begin() + end),
                 options.matching.use_simd, &cache);
    // The pipeline passes pair indices only; each result waits in a slot owned here. oneTBB
    // allocates a token for a non-trivial type (a shared_ptr) and frees it only when the next
    // filter's body returns, so an error or a kill (an exception) inside the pipeline leaked the
    // results in flight; the slots are freed by unwinding like any other local.
    std::vector<std::unique_ptr<PairResult>> results(end - begin);
    size_t next = begin;
    const auto feed = [&](tbb::flow_control& control) -> size_t {
      if (next == end) {
        control.stop();
        return end;
      }
      return next++;
    };
    const auto verify = [&](size_t k) {
      const auto [id1, id2] = pairs[k];
      results[k - begin] = std::make_unique<PairResult>(
          MatchPair(*cache.at(id1), *cache.at(id2), id1, id2, options));
      return k;
    };
    const auto write = [&](size_t k) {
      writer.Write(pairs[k].first, pairs[k].second, *results[k - begin]);
      results[k - begin].reset();
      progress.Tick();
    };
    // Tokens bound the results waiting for a slow pair ahead of them.
    tbb::parallel_pipeline(
        2 * static_cast<size_t>(tbb::this_task_arena::max_concurrency()),
        tbb::make_filter<void, size_t>(tbb::filter_mode::serial_in_order, feed) &
            tbb::make_filter<size_t, size_t>(tbb::filter_mode::parallel, verify) &
            tbb::make_filter<size_t, void>(tbb::filter_mode::serial_in_order, write));
  }
  writer.Finish();
  progress.Finish();
}

ImagePairs SelectPairs(const Database& db, const std::vector<image_t>& ids, MatchStrategy strategy,
                       const MatchOptions& options) {
  switch (strategy) {
    case MatchStrategy::kRetrieval:
      return RetrievedPairs(
          ids, RetrieveNeighbors(db, ids, std::vector<bool>(ids.size(), true), options));
    case MatchStrategy::kSequential: {
      if (options.loop_interval == 0) return SequentialPairs(ids, options.overlap);
      std::vector<bool> is_query(ids.size(), false);
      for (size_t i = 0; i < ids.size(); i += static_cast<size_t>(options.loop_interval))
        is_query[i] = true;
      return SequentialLoopPairs(
          ids, options.overlap, options.loop_interval,
          RetrieveNeighbors(db, ids, is_query, options, static_cast<size_t>(options.overlap)));
    }
    case MatchStrategy::kExhaustive:
    case MatchStrategy::kAuto:
      break;
  }
  return ExhaustivePairs(ids);
}

}  // namespace

void MatchOptions::Check() const {
  CheckAtLeast("--overlap", overlap, 1);
  CheckNonNegative("--loop-interval", loop_interval);
  retrieval.Check();
  vocabulary.Check();
  CheckAtLeast("--vocabulary-sample", vocabulary_sample, 1000);
  if (!vocabulary_file.empty() && std::filesystem::is_directory(vocabulary_file))
    FailOption("--vocabulary", "a file", vocabulary_file.string());
  matching.Check();
  verification.Check();
  CheckNonNegative("--threads", num_threads);
  CheckPositive("commit_interval", commit_interval);
}

MatchSummary RunMatching(const MatchOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  // Checked before opening: Database would create a missing file.
  if (!std::filesystem::is_regular_file(options.workspace)) {
    Fail("workspace {} does not exist (run `varsfm extract` first)", options.workspace.string());
  }
  std::unique_ptr<tbb::global_control> threads;
  if (options.num_threads > 0) {
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    options.num_threads);
  }
  const PathLock lock(options.workspace);
  Timer timer;
  Database db(options.workspace);
  const std::vector<DbImage> images = ImagesWithFeatures(db);
  if (images.size() < 2) {
    Fail("workspace {} has {} image(s) with features; matching needs at least 2",
         options.workspace.string(), images.size());
  }
  std::vector<image_t> ids;
  for (const DbImage& image : images) ids.push_back(image.image_id);
  MatchSummary summary;
  summary.strategy = options.strategy;
  if (summary.strategy == MatchStrategy::kAuto)
    summary.strategy = images.size() > kAutoRetrievalImages ? MatchStrategy::kRetrieval
                                                            : MatchStrategy::kExhaustive;
  const ImagePairs all_pairs = SelectPairs(db, ids, summary.strategy, options);
  summary.num_images = images.size();
  summary.num_pairs = all_pairs.size();
  ResultSettings record(db);
  const int64_t settings = record.Id("match", MatchSettings(options));
  const ImagePairs pairs = PairsToMatch(db, record, settings, all_pairs, summary);
  info("match: {} images, {} {} pairs ({} already verified)", images.size(), all_pairs.size(),
       NameOf(kMatchStrategyNames, summary.strategy), summary.num_skipped);

  MatchPairs(db, record, settings, pairs, options, summary);
  info("match: {} of {} new pairs verified, {} inlier matches, {:.1f} s", summary.num_verified,
       pairs.size(), summary.num_inlier_matches, timer.Seconds());
  if (!pairs.empty() && summary.num_verified == 0 && summary.num_skipped == 0)
    warn(
        "match: no pair of images shares a verified geometry: the photos do not overlap, or have "
        "too few features (see extract's warnings); a model needs at least one pair");
  return summary;
}

}  // namespace varsfm
