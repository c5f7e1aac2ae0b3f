#include "varsfm/util/byte_budget.h"

#include <chrono>
#include <future>
#include <optional>

#include <gtest/gtest.h>

namespace varsfm {
namespace {

using std::chrono::milliseconds;

TEST(ByteBudget, LeasesThatFitTogetherProceedAndEndWithTheirScope) {
  ByteBudget budget(100);
  {
    const ByteBudget::Lease a = budget.Acquire(40);
    const ByteBudget::Lease b = budget.Acquire(60);
    EXPECT_EQ(budget.HeldBytes(), 100u);
  }
  EXPECT_EQ(budget.HeldBytes(), 0u);
}

TEST(ByteBudget, ARequestThatDoesNotFitWaitsForARelease) {
  ByteBudget budget(100);
  std::optional<ByteBudget::Lease> held(budget.Acquire(70));
  auto waiter = std::async(std::launch::async, [&] {
    const ByteBudget::Lease lease = budget.Acquire(50);
    return budget.HeldBytes();
  });
  // 70 + 50 > 100: still waiting (a wrong budget would have returned at once).
  EXPECT_EQ(waiter.wait_for(milliseconds(100)), std::future_status::timeout);
  EXPECT_EQ(budget.HeldBytes(), 70u);
  held.reset();
  EXPECT_EQ(waiter.get(), 50u);  // it held its 50 bytes alone
  EXPECT_EQ(budget.HeldBytes(), 0u);
}

TEST(ByteBudget, ARequestLargerThanTheCapacityRunsAloneRatherThanNever) {
  ByteBudget budget(100);
  std::optional<ByteBudget::Lease> big(budget.Acquire(250));  // nothing held: proceeds
  EXPECT_EQ(budget.HeldBytes(), 250u);
  auto small = std::async(std::launch::async, [&] {
    const ByteBudget::Lease lease = budget.Acquire(1);
    return budget.HeldBytes();
  });
  EXPECT_EQ(small.wait_for(milliseconds(100)), std::future_status::timeout);
  big.reset();
  EXPECT_EQ(small.get(), 1u);
  EXPECT_EQ(budget.HeldBytes(), 0u);
}

TEST(ByteBudget, CapacityZeroIsUnbounded) {
  ByteBudget budget(0);
  const ByteBudget::Lease a = budget.Acquire(size_t{1} << 40);
  const ByteBudget::Lease b = budget.Acquire(size_t{1} << 40);
  EXPECT_EQ(budget.HeldBytes(), size_t{2} << 40);
}

TEST(ByteBudget, AMovedLeaseIsReleasedOnce) {
  ByteBudget budget(10);
  {
    ByteBudget::Lease a = budget.Acquire(10);
    const ByteBudget::Lease b = std::move(a);
    EXPECT_EQ(budget.HeldBytes(), 10u);
  }
  EXPECT_EQ(budget.HeldBytes(), 0u);
}

}  // namespace
}  // namespace varsfm
