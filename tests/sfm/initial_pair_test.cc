#include "varsfm/sfm/initial_pair.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace varsfm {
namespace {

std::vector<std::pair<int, bool>> Order(const std::vector<InitialPairAttempt>& attempts) {
  std::vector<std::pair<int, bool>> order;
  for (const InitialPairAttempt& a : attempts) order.emplace_back(a.candidate, a.accept_degenerate);
  return order;
}

// A degenerate calibration is accepted only after every usable candidate, well-conditioned or
// not, has been tried without it: the top-ranked pair (0) is not taken with the prior's focal
// length while a lower one may calibrate.
TEST(InitialPairAttempts, DegenerateCalibrationsAreTheLastResort) {
  const std::vector<bool> usable = {true, true, false, true};
  const std::vector<bool> well_conditioned = {false, true, true, false};
  const std::vector<std::pair<int, bool>> expected = {{1, false}, {0, false}, {3, false},
                                                      {0, true},  {1, true},  {3, true}};
  EXPECT_EQ(Order(InitialPairAttempts(usable, well_conditioned)), expected);
}

TEST(InitialPairAttempts, NoUsableCandidateNoAttempt) {
  EXPECT_TRUE(InitialPairAttempts({}, {}).empty());
  EXPECT_TRUE(InitialPairAttempts({false, false}, {true, false}).empty());
}

}  // namespace
}  // namespace varsfm
