// Recall of retrieval against exhaustive matching for several k at once, without matching: the
// pairs each k selects (the ranked neighbours of each image, cut at k) against the verified pairs
// of an exhaustively matched workspace, counted by pairs and weighted by inliers (issue 21's
// recall). Also sequential pairs with loop closure. Used to choose the default k.
//   retrieval_recall WORKSPACE K... [--expansion M] [--overlap N --loop-interval M]
#include <algorithm>
#include <cstdio>
#include <exception>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "varsfm/io/database.h"
#include "varsfm/matching/pair_selection.h"
#include "varsfm/pipeline/retrieval_neighbors.h"
#include "varsfm/util/timer.h"

int main(int argc, char** argv) {
  using namespace varsfm;
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: %s WORKSPACE K... [--expansion M] [--overlap N] "
                 "[--loop-interval M]\n",
                 argv[0]);
    return 2;
  }
  try {
    const Database db(argv[1]);
    std::vector<int> ks;
    MatchOptions options;
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--expansion" && i + 1 < argc)
        options.retrieval.query_expansion = std::stoi(argv[++i]);
      else if (a == "--overlap" && i + 1 < argc)
        options.overlap = std::stoi(argv[++i]);
      else if (a == "--loop-interval" && i + 1 < argc)
        options.loop_interval = std::stoi(argv[++i]);
      else
        ks.push_back(std::stoi(a));
    }
    std::vector<DbImage> images = db.ReadAllImages();
    std::sort(images.begin(), images.end(),
              [](const DbImage& a, const DbImage& b) { return a.name < b.name; });
    std::vector<image_t> ids;
    for (const DbImage& image : images) ids.push_back(image.image_id);
    std::map<image_pair_t, size_t> reference;
    size_t total = 0;
    for (const auto& [pair, geometry] : db.ReadAllTwoViewGeometries())
      if (!geometry.inlier_matches.empty()) {
        reference[pair] = geometry.inlier_matches.size();
        total += geometry.inlier_matches.size();
      }
    const auto report = [&](const std::string& name, const ImagePairs& pairs, double seconds) {
      std::set<image_pair_t> selected;
      for (const auto& [a, b] : pairs) selected.insert(Database::ImagePairToPairId(a, b));
      size_t found = 0, found_pairs = 0;
      for (const auto& [pair, inliers] : reference)
        if (selected.contains(pair)) found += inliers, ++found_pairs;
      std::printf(
          "%s: %zu pairs, recall %.4f of %zu verified pairs, %.4f weighted by inliers, "
          "retrieval %.1f s\n",
          name.c_str(), pairs.size(), static_cast<double>(found_pairs) / reference.size(),
          reference.size(), static_cast<double>(found) / total, seconds);
    };
    // Neighbours come ranked: those of a smaller k are the first k of the largest k's.
    options.retrieval.num_neighbors = *std::max_element(ks.begin(), ks.end());
    std::vector<bool> is_query(ids.size(), options.loop_interval == 0);
    for (size_t i = 0; options.loop_interval > 0 && i < ids.size(); i += options.loop_interval)
      is_query[i] = true;
    Timer timer;
    const auto ranked = RetrieveNeighbors(db, ids, is_query, options,
                                          options.loop_interval > 0 ? options.overlap : 0);
    const double seconds = timer.Seconds();
    for (const int k : ks) {
      auto neighbors = ranked;
      for (auto& list : neighbors) list.resize(std::min(list.size(), static_cast<size_t>(k)));
      if (options.loop_interval > 0)
        report("sequential " + std::to_string(options.overlap) + " + loop every " +
                   std::to_string(options.loop_interval) + ", k " + std::to_string(k),
               SequentialLoopPairs(ids, options.overlap, options.loop_interval, neighbors),
               seconds);
      else
        report("retrieval k " + std::to_string(k), RetrievedPairs(ids, neighbors), seconds);
    }
    if (options.loop_interval > 0)
      report("sequential " + std::to_string(options.overlap), SequentialPairs(ids, options.overlap),
             0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retrieval_recall: %s\n", e.what());
    return 1;
  }
  return 0;
}
