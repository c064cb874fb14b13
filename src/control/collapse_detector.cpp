#include "lathectl/control/collapse_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lathectl::control {

// (The ring's index wraps by a mask: kCapacity is a power of two. push() ages the queue itself
// rather than through pass(): it runs every control period, and the call was a third of its
// cost.)
static_assert((CollapseDetector::kCapacity & (CollapseDetector::kCapacity - 1)) == 0);

void CollapseDetector::age_by(double elapsed) noexcept {
  constexpr std::size_t kMask = kCapacity - 1;
  for (std::size_t k = 0, i = head_; k < size_; ++k, i = (i + 1) & kMask) ring_[i].age += elapsed;
  while (size_ > 0 && !(ring_[head_].age <= window_)) {  // out of the window: never counts again
    head_ = (head_ + 1) & kMask;
    --size_;
  }
}

void CollapseDetector::pass(double elapsed) noexcept { age_by(elapsed); }

void CollapseDetector::push(double x, double elapsed, bool keep) noexcept {
  constexpr std::size_t kMask = kCapacity - 1;
  for (std::size_t k = 0, i = head_; k < size_; ++k, i = (i + 1) & kMask) ring_[i].age += elapsed;
  while (size_ > 0 && !(ring_[head_].age <= window_)) {
    head_ = (head_ + 1) & kMask;
    --size_;
  }
  ++pushed_;
  if (!keep || !std::isfinite(x)) return;
  while (size_ > 0 && ring_[(head_ + size_ - 1) & kMask].x <= x) --size_;  // never the largest
  if (size_ == kCapacity) {  // full: forget the oldest
    head_ = (head_ + 1) & kMask;
    --size_;
  }
  ring_[(head_ + size_) & kMask] = {x, 0.0};
  ++size_;
}

double CollapseDetector::peak() const noexcept {
  return size_ > 0 ? ring_[head_].x : -std::numeric_limits<double>::infinity();
}

bool CollapseDetector::fell_by(double x, double drop) const noexcept {
  const double top = std::max(x, peak());
  return top - x > drop;
}

}  // namespace lathectl::control
