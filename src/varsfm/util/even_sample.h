#pragma once
// An even sample of a stream whose length is not known in advance: every k-th item from the
// first, k a power of two that doubles (dropping every other item kept) whenever twice the cap
// are kept. Fewer than 2 x cap items (at least cap once that many came), the same ones for the
// same stream.
#include <cstddef>
#include <utility>
#include <vector>

namespace varsfm {

template <typename T>
class EvenSample {
 public:
  explicit EvenSample(size_t cap) : cap_(cap > 0 ? cap : 1) {}

  void Add(const T& item) {
    if (seen_++ % stride_ != 0) return;
    items_.push_back(item);
    if (items_.size() < 2 * cap_) return;
    // From the second: item 0 stays where it is (a self-move would empty a vector or a string).
    for (size_t i = 1; 2 * i < items_.size(); ++i) items_[i] = std::move(items_[2 * i]);
    items_.resize((items_.size() + 1) / 2);
    stride_ *= 2;
  }

  const std::vector<T>& items() const { return items_; }

 private:
  size_t cap_;
  size_t stride_ = 1;
  size_t seen_ = 0;
  std::vector<T> items_;
};

}  // namespace varsfm
