#include "varsfm/util/random.h"

#include <gtest/gtest.h>

namespace varsfm {

TEST(DeriveSeed, DistinctPerIndexAndStable) {
  EXPECT_EQ(DeriveSeed(7, 3), DeriveSeed(7, 3));
  EXPECT_NE(DeriveSeed(7, 3), DeriveSeed(7, 4));
  EXPECT_NE(DeriveSeed(7, 3), DeriveSeed(8, 3));
}

}  // namespace varsfm
