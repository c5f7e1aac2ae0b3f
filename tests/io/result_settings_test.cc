// The record of the settings each stored result was made with, beside COLMAP's tables.
#include "varsfm/io/result_settings.h"

#include <gtest/gtest.h>

#include "support/test_data.h"

namespace varsfm {
namespace {

using testing::TempDir;

TEST(ResultSettings, IdsAreStablePerStageAndText) {
  TempDir dir("settings_ids");
  Database db(dir.path() / "ws.db");
  ResultSettings record(db);
  const int64_t a = record.Id("extract", "{\"max_features\":8192}");
  const int64_t b = record.Id("extract", "{\"max_features\":300}");
  const int64_t c = record.Id("match", "{\"max_features\":8192}");
  EXPECT_NE(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(record.Id("extract", "{\"max_features\":8192}"), a);
  // Kept across connections.
  ResultSettings again(db);
  EXPECT_EQ(again.Id("extract", "{\"max_features\":300}"), b);
}

TEST(ResultSettings, ImageAndPairRecordsAreWrittenReadAndDeleted) {
  TempDir dir("settings_records");
  Database db(dir.path() / "ws.db");
  ResultSettings record(db);
  const int64_t settings = record.Id("extract", "x");
  const int64_t other = record.Id("extract", "y");
  const camera_t camera = db.WriteCamera({0, 0, 100, 80, {90, 50, 40}, false});
  const image_t image1 = db.WriteImage({0, "a.jpg", camera});
  const image_t image2 = db.WriteImage({0, "b.jpg", camera});
  record.WriteImageSettings(image1, settings);
  record.WriteImageSettings(image2, settings);
  record.WriteImageSettings(image2, other);  // replaces
  EXPECT_EQ(record.ReadImageSettings(),
            (std::unordered_map<image_t, int64_t>{{image1, settings}, {image2, other}}));

  record.WritePairSettings(image2, image1, settings);  // either order, one pair
  EXPECT_EQ(record.ReadPairSettings(),
            (std::unordered_map<image_pair_t, int64_t>{
                {Database::ImagePairToPairId(image1, image2), settings}}));
  record.DeletePairSettings(image1, image2);
  EXPECT_TRUE(record.ReadPairSettings().empty());

  // An image's record goes with the image.
  db.DeleteImage(image1);
  EXPECT_EQ(record.ReadImageSettings(), (std::unordered_map<image_t, int64_t>{{image2, other}}));
}

}  // namespace
}  // namespace varsfm
