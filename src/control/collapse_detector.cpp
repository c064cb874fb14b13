#include "lathectl/control/collapse_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lathectl::control {

void CollapseDetector::age_by(double elapsed) noexcept {
  for (std::size_t k = 0; k < size_; ++k) at(k).age += elapsed;
  while (size_ > 0 && !(at(0).age <= window_)) {  // out of the window: never counts again
    head_ = (head_ + 1) % kCapacity;
    --size_;
  }
}

void CollapseDetector::pass(double elapsed) noexcept { age_by(elapsed); }

void CollapseDetector::push(double x, double elapsed, bool keep) noexcept {
  age_by(elapsed);
  ++pushed_;
  if (!keep || !std::isfinite(x)) return;
  while (size_ > 0 && at(size_ - 1).x <= x) --size_;  // never the largest again
  if (size_ == kCapacity) {  // full: forget the oldest
    head_ = (head_ + 1) % kCapacity;
    --size_;
  }
  at(size_) = {x, 0.0};
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
