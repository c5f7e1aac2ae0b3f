#include "varsfm/sfm/correspondence_graph.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(CorrespondenceGraph, KeepsThePairsFundamentalMatrixForEitherOrder) {
  CorrespondenceGraph graph;
  for (const image_t id : {1, 2, 3}) graph.AddImage(id, 4);
  Eigen::Matrix3d F;
  F << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  // Given for 3 -> 1 (x1^T F x3 = 0): 1 -> 3 is its transpose.
  graph.AddImagePair(3, 1, {{0, 1}, {2, 3}}, F);
  graph.AddImagePair(1, 2, {{0, 0}});
  ASSERT_TRUE(graph.FundamentalMatrix(3, 1).has_value());
  EXPECT_EQ(*graph.FundamentalMatrix(3, 1), F);
  EXPECT_EQ(*graph.FundamentalMatrix(1, 3), F.transpose());
  // A pair added without F, and a pair never added, have none.
  EXPECT_FALSE(graph.FundamentalMatrix(1, 2).has_value());
  EXPECT_FALSE(graph.FundamentalMatrix(2, 3).has_value());
  // The matches are those of the order asked.
  EXPECT_EQ(graph.MatchesBetween(1, 3), (FeatureMatches{{1, 0}, {3, 2}}));
}

}  // namespace
}  // namespace varsfm
