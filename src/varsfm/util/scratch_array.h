#pragma once
// A fixed-size array of plain elements on the heap, which its owner may move into
// scratch memory (scratch_memory.h) once it is filled: the per-pixel arrays of a view's depth
// map, made one view at a time and read again only after every view has one.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "varsfm/util/scratch_memory.h"

namespace varsfm {

// T is copied as bytes: plain values and Eigen's fixed-size vectors (which declare their own
// copy constructor but hold nothing else).
template <typename T>
class ScratchArray {
  static_assert(std::is_trivially_destructible_v<T> && std::is_standard_layout_v<T>);

 public:
  using value_type = T;
  using iterator = T*;
  using const_iterator = const T*;

  ScratchArray() = default;
  // A copy is on the heap, wherever the original lies.
  ScratchArray(const ScratchArray& other) : heap_(other.begin(), other.end()) { PointAtHeap(); }
  ScratchArray& operator=(const ScratchArray& other) {
    if (this != &other) *this = ScratchArray(other);
    return *this;
  }
  ScratchArray(ScratchArray&& other) noexcept { *this = std::move(other); }
  ScratchArray& operator=(ScratchArray&& other) noexcept {
    heap_ = std::move(other.heap_);
    scratch_ = std::move(other.scratch_);
    data_ = other.data_;
    size_ = other.size_;
    other.heap_.clear();
    other.scratch_.reset();
    other.data_ = nullptr;
    other.size_ = 0;
    return *this;
  }

  // n copies of `value`, on the heap.
  void assign(size_t n, const T& value) {
    scratch_.reset();
    heap_.assign(n, value);
    PointAtHeap();
  }

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }

  bool InScratch() const { return scratch_ != nullptr; }

  friend bool operator==(const ScratchArray& a, const ScratchArray& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  }

  // Moves the elements to `memory` at byte `offset` (a multiple of alignof(T), with room for
  // them) and frees the heap copy; the array then shares `memory`.
  void MoveTo(std::shared_ptr<ScratchMemory> memory, size_t offset) {
    T* target = reinterpret_cast<T*>(static_cast<char*>(memory->data()) + offset);
    if (size_ > 0) std::memcpy(static_cast<void*>(target), data_, size_ * sizeof(T));
    std::vector<T>().swap(heap_);
    scratch_ = std::move(memory);
    data_ = target;
  }

 private:
  void PointAtHeap() {
    data_ = heap_.data();
    size_ = heap_.size();
  }

  std::vector<T> heap_;
  std::shared_ptr<ScratchMemory> scratch_;
  T* data_ = nullptr;
  size_t size_ = 0;
};

// Where each of arrays of the given byte sizes and alignment starts in one block, and the
// block's size: a view's arrays share one mapping (a process may hold only so many, ~65k).
struct ScratchLayout {
  std::vector<size_t> offsets;
  size_t bytes = 0;
  void Add(size_t size, size_t alignment) {
    bytes = (bytes + alignment - 1) / alignment * alignment;
    offsets.push_back(bytes);
    bytes += size;
  }
};

}  // namespace varsfm
