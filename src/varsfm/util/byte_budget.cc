#include "varsfm/util/byte_budget.h"

namespace varsfm {

ByteBudget::Lease::~Lease() {
  if (budget_) budget_->Release(bytes_);
}

ByteBudget::Lease ByteBudget::Acquire(size_t bytes) {
  std::unique_lock lock(mutex_);
  released_.wait(lock, [&] { return capacity_ == 0 || held_ == 0 || held_ + bytes <= capacity_; });
  held_ += bytes;
  return Lease(this, bytes);
}

size_t ByteBudget::HeldBytes() const {
  const std::lock_guard lock(mutex_);
  return held_;
}

void ByteBudget::Release(size_t bytes) {
  {
    const std::lock_guard lock(mutex_);
    held_ -= bytes;
  }
  released_.notify_all();
}

}  // namespace varsfm
