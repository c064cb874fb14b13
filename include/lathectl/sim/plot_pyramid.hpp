#pragma once
// Min/max pyramid of one plotted series, for the reports' interactive plots: level 0
// holds the samples themselves, level k ≥ 1 the minimum and the maximum of each bucket of
// branching^k samples, in the order they occurred (so a spike or a zig-zag keeps its shape). A
// viewer picks, for the visible x range, the coarsest level that still gives about one point per
// pixel; zoomed in far enough, that is level 0 and it shows the recorded samples.
//
// Fed one sample at a time (push), with memory bounded by Options::max_values_per_level per
// level: a level that would grow beyond it is dropped (its coarser levels carry on), so a series
// can be fed while it streams and still fits a report's size budget. It is also the streamed
// recorder's plot storage (recorder.hpp): the static SVG takes points() from it, the interactive
// chart its levels. Values are stored as float
// (what the page decodes), x as an offset from the first sample when the spacing is not uniform.

#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace lathectl::sim {

class PlotPyramid {
 public:
  struct Options {
    std::size_t branching = 4;                 // samples per bucket grow by this per level
    std::size_t max_values_per_level = 1u << 14;  // a level beyond this is dropped
    std::size_t coarsest_values = 2048;        // levels above the first this small are not kept
  };
  struct Level {
    std::size_t bucket = 1;  // samples per bucket; 1 for level 0
    // Level 0: one value per sample. Level k: two values per bucket (its extremes, in the order
    // they occurred); NaN where a bucket had no finite value.
    std::vector<float> y;
    // Empty when the x spacing is uniform; else the x of each value (offset from x0()).
    std::vector<float> x;
  };

  PlotPyramid() : PlotPyramid(Options{}) {}
  explicit PlotPyramid(Options options);

  // The next sample. A sample with a non-finite x is skipped (it cannot be placed); a non-finite
  // y is kept (level 0 shows it as a gap).
  void push(double x, double y);
  // The next sample of several series against the same x (a streamed recorder's channels against
  // its time): series[i].push(x, y[i]) for each i < min(sizes). Those fed the same x's as the
  // first (as many samples) take its bookkeeping of x instead of repeating it.
  static void push_row(std::span<PlotPyramid> series, double x, std::span<const double> y);
  // Closes the partial buckets; push() after finish() is an error (std::logic_error).
  void finish();

  [[nodiscard]] std::size_t samples() const noexcept { return samples_; }
  [[nodiscard]] double x0() const noexcept { return x0_; }
  [[nodiscard]] double x_last() const noexcept { return last_x_; }  // of the last sample kept
  // Uniform spacing: sample i lies at x0() + i·dx() (to 1e-3 of dx); then levels() hold no x,
  // and a viewer places level 0's value i at i·dx, level k's pair j at (j·b + b/4) and
  // (j·b + 3b/4) samples (b the bucket).
  [[nodiscard]] bool uniform() const noexcept { return uniform_; }
  [[nodiscard]] double dx() const noexcept { return dx_; }
  // x never decreases (a time axis); a viewer may binary-search it.
  [[nodiscard]] bool monotonic() const noexcept { return monotonic_; }
  // After finish(): the kept levels, finest first (level 0 absent when it was dropped).
  [[nodiscard]] const std::vector<Level>& levels() const;
  // A finished copy (this one unchanged; itself when already finished and shared).
  [[nodiscard]] std::shared_ptr<const PlotPyramid> finished() const;
  // At most max_points points for a static plot, from the finest kept level that has no more
  // values (the coarsest when none), in order; works before finish() too (on a finished copy).
  void points(std::vector<double>& x, std::vector<double>& y,
              std::size_t max_points = 4096) const;

 private:
  // The bucket being filled at one level ≥ 1. Empty (no finite value yet): lo = +inf, hi = -inf
  // (a finite value is clamped below ±3e38 as a float, a gap is NaN: both compare false), so
  // taking an extreme is one comparison each, with no flag. x offsets are kept as the floats
  // stored; while the bucket has no finite value, both are its first sample's.
  struct Bucket {
    float lo = kEmptyLo, hi = kEmptyHi;
    float x_lo = 0.0f, x_hi = 0.0f;
    std::size_t count = 0;
    bool lo_first = true;  // the minimum occurred no later than the maximum
  };
  static constexpr float kEmptyLo = std::numeric_limits<float>::infinity();
  static constexpr float kEmptyHi = -std::numeric_limits<float>::infinity();
  static void merge(Bucket& o, const Bucket& b) noexcept;  // b (later samples) into o
  void track_x(double x) noexcept;
  void push_value(double y, float off);
  void add_level();
  void close(std::size_t level, bool propagate = true);  // and the fuller ones above it
  void drop(std::size_t level);

  Options opt_;
  std::vector<Level> levels_;
  std::vector<Bucket> open_;            // per level ≥ 1 (index = level)
  std::vector<unsigned char> dropped_;  // per level
  std::size_t samples_ = 0;
  double x0_ = 0.0, dx_ = 0.0, last_x_ = 0.0;
  bool uniform_ = true, monotonic_ = true, finished_ = false;
};

}  // namespace lathectl::sim
