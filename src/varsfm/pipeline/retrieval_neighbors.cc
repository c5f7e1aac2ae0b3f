#include "varsfm/pipeline/retrieval_neighbors.h"

#include <algorithm>
#include <filesystem>

#include <tbb/parallel_for.h>

#include "varsfm/matching/image_retrieval.h"
#include "varsfm/matching/vocabulary_tree_io.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// An even share of the training sample from every image: rows spread evenly over each image's
// descriptors (no random draw: the sample depends on the workspace alone).
TrainingDescriptors TrainingSample(const Database& db, const std::vector<image_t>& images,
                                   size_t sample_size) {
  const size_t per_image = (sample_size + images.size() - 1) / images.size();
  std::vector<FeatureDescriptors> parts;
  size_t total = 0;
  for (const image_t id : images) {
    const FeatureDescriptors descriptors = db.ReadDescriptors(id);
    if (descriptors.rows() > 0 && descriptors.cols() != VocabularyTree::kDimension)
      Fail("image {} has descriptors of {} values; retrieval needs {}", id, descriptors.cols(),
           VocabularyTree::kDimension);
    const size_t rows = static_cast<size_t>(descriptors.rows());
    const size_t take = std::min(rows, per_image);
    FeatureDescriptors part(static_cast<Eigen::Index>(take), VocabularyTree::kDimension);
    for (size_t t = 0; t < take; ++t)
      part.row(static_cast<Eigen::Index>(t)) =
          descriptors.row(static_cast<Eigen::Index>(t * rows / take));
    total += take;
    parts.push_back(std::move(part));
  }
  TrainingDescriptors sample(static_cast<Eigen::Index>(total), VocabularyTree::kDimension);
  Eigen::Index row = 0;
  for (const FeatureDescriptors& part : parts) {
    sample.middleRows(row, part.rows()) = part.cast<float>();
    row += part.rows();
  }
  return sample;
}

VocabularyTree LoadOrTrain(const Database& db, const std::vector<image_t>& images,
                           const MatchOptions& options) {
  const std::filesystem::path& file = options.vocabulary_file;
  if (!file.empty() && std::filesystem::exists(file)) {
    VocabularyTree tree = ReadVocabularyTree(file);
    info("match: vocabulary tree {} ({} words)", file.string(), tree.NumWords());
    return tree;
  }
  Timer timer;
  const TrainingDescriptors sample =
      TrainingSample(db, images, static_cast<size_t>(options.vocabulary_sample));
  VocabularyTreeOptions tree_options = options.vocabulary;
  tree_options.seed = options.seed;
  // MatchOptions::Check checked options.vocabulary; the seed is any value.
  VocabularyTree tree = VocabularyTree::Train(sample, tree_options, OptionsCheck::kDoneByCaller);
  info("match: vocabulary tree of {} words trained on {} descriptors, {:.1f} s", tree.NumWords(),
       sample.rows(), timer.Seconds());
  if (!file.empty()) {
    WriteVocabularyTree(tree, file);
    info("match: vocabulary tree saved to {}", file.string());
  }
  return tree;
}

}  // namespace

std::vector<std::vector<uint32_t>> RetrieveNeighbors(const Database& db,
                                                     const std::vector<image_t>& images,
                                                     const std::vector<bool>& is_query,
                                                     const MatchOptions& options,
                                                     size_t exclude_radius) {
  const VocabularyTree tree = LoadOrTrain(db, images, options);
  Timer timer;
  std::vector<std::vector<int>> words(images.size());
  for (size_t i = 0; i < images.size(); ++i)
    words[i] = tree.Quantize(db.ReadDescriptors(images[i]));
  const RetrievalIndex index(words, tree.NumWords(), options.retrieval.scoring);
  std::vector<std::vector<uint32_t>> neighbors(images.size());
  tbb::parallel_for(size_t{0}, images.size(), [&](size_t i) {
    if (is_query[i]) neighbors[i] = index.Neighbors(i, options.retrieval, exclude_radius);
  });
  info("match: {} images quantized and queried, {:.1f} s", images.size(), timer.Seconds());
  return neighbors;
}

}  // namespace varsfm
