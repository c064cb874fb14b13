#pragma once
// "Did the load collapse within a window": the one detector of a broken tool's edge by the fall of
// its load, which AdaptiveFeedController (breakage_drop_window_s), PathBreakage (AdaptiveMachine's
// path-aware one) and SlideMachine (breakage_window_s) use.
//
// It keeps the trailing window's largest samples (a monotonic queue: a sample that a newer, larger
// one follows can never be the window's largest again, so it is dropped) in a fixed ring; the
// stepping calls never allocate. What differs between its users is a parameter of theirs:
//   the window's unit  the unit of `elapsed` the caller hands each call: seconds of measured time
//                      (PeriodTime::elapsed_s: AdaptiveFeedController, PathBreakage — a late
//                      period only widens the window) or samples (elapsed 1 per push: SlideMachine,
//                      one push per control period). A sample counts while its age, the sum of the
//                      elapsed handed since it (in that order, from 0), is ≤ the window.
//   the question       a fall from a level to another (fell_to: the caller pushes only the samples
//                      above its upper level, judged with that sample's own level, e.g. half the
//                      limit then in force; "collapsed" is a sample within the window and x below
//                      the lower level) or by an absolute amount (fell_by: x more than `drop` below
//                      the window's largest sample; a relative drop is the caller's drop × its
//                      reference).
// Capacity: kCapacity samples kept (those that may still be the largest). Past that the oldest is
// forgotten: fell_to stays exact (the newest sample is always kept), fell_by is exact while the
// window spans at most kCapacity samples (SlideMachine checks its window against it).
#include <array>
#include <cstddef>

namespace lathectl::control {

class CollapseDetector {
 public:
  static constexpr std::size_t kCapacity = 256;
  CollapseDetector() = default;
  explicit CollapseDetector(double window) noexcept { configure(window); }
  // The window in the unit of `elapsed` (≥ 0); forgets the history.
  void configure(double window) noexcept {
    window_ = window;
    reset();
  }
  [[nodiscard]] double window() const noexcept { return window_; }
  // Forget the history (a new cut, a rapid, a restart).
  void reset() noexcept {
    head_ = 0;
    size_ = 0;
    pushed_ = 0;
  }
  // Time passes with no sample to judge (a reading that cannot be separated from something else).
  void pass(double elapsed) noexcept;
  // Time passes, then x is the newest sample — if `keep` (fell_to's callers keep only the samples
  // above their upper level) and x is finite; else time only passes.
  void push(double x, double elapsed, bool keep = true) noexcept;
  // Samples pushed since the last reset (non-finite ones included).
  [[nodiscard]] std::size_t pushed() const noexcept { return pushed_; }
  // A sample within the window.
  [[nodiscard]] bool any() const noexcept { return size_ > 0; }
  // The window's largest sample (−∞ when there is none).
  [[nodiscard]] double peak() const noexcept;
  // Collapsed from a level: a sample (pushed as above the upper level) within the window, and x
  // below `low`.
  [[nodiscard]] bool fell_to(double x, double low) const noexcept { return x < low && any(); }
  // Collapsed by an amount: x lies more than `drop` below the largest of x and the window's
  // samples (false for a non-finite x).
  [[nodiscard]] bool fell_by(double x, double drop) const noexcept;

 private:
  struct Sample {
    double x = 0.0;
    double age = 0.0;
  };
  [[nodiscard]] Sample& at(std::size_t k) noexcept { return ring_[(head_ + k) % kCapacity]; }
  void age_by(double elapsed) noexcept;

  std::array<Sample, kCapacity> ring_{};  // the queue: oldest (largest) at head_
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::size_t pushed_ = 0;
  double window_ = 0.0;
};

}  // namespace lathectl::control
