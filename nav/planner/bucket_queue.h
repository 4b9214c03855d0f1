// A monotone bucket priority queue: keys are non-negative and never pushed below the bucket being popped. Keys
// within one bucket come out in arrival order, so the ordering is exact only to `quantum`. O(1) per operation,
// which is what makes it worth having over a binary heap for fast marching (Yatziv, Bartesaghi and Sapiro, J. Comput.
// Phys. 2006) and for A* with a consistent heuristic (whose f never decreases along the search).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace corridor::nav {

class BucketQueue {
 public:
  // `expected_max_key` sizes the buckets up front; larger keys grow them.
  BucketQueue(double quantum, double expected_max_key)
      : inverse_quantum_(1.0 / quantum), buckets_(static_cast<std::size_t>(expected_max_key / quantum) + 2) {}

  void Push(double key, int value) {
    std::size_t b = static_cast<std::size_t>(std::max(0.0, key) * inverse_quantum_);
    b = std::max(b, current_);  // a key in an already-popped bucket goes to the current one
    if (b >= buckets_.size()) buckets_.resize(b + b / 2 + 1);
    buckets_[b].push_back(value);
  }

  // The next value, or -1 when the queue is empty.
  int Pop() {
    while (current_ < buckets_.size()) {
      std::vector<int>& bucket = buckets_[current_];
      if (read_ < bucket.size()) return bucket[read_++];
      bucket.clear();
      read_ = 0;
      ++current_;
    }
    return -1;
  }

 private:
  double inverse_quantum_;
  std::vector<std::vector<int>> buckets_;
  std::size_t current_ = 0;
  std::size_t read_ = 0;
};

}  // namespace corridor::nav
