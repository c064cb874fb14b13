#pragma once
// System C's profile errors, row by row as the tracer rig records (a RowSink on its
// streamed recorder, so a run's memory does not grow with the template's length, the feed or the
// record interval). Each number is the one the recorded columns gave, to the bit: the same rows
// in the same order enter the same sums and extremes.
//  - the largest |δx|, |δy| of the run and of each feature along the profile (by the tool's x;
//    a shoulder's zone belongs to the shoulder),
//  - on each cone's second half (by the carriage's x): the steady lag (the last one) and the
//    waviness, the peak-to-peak of δy about its least-squares line. The line is known only at the
//    end, so the window's (x, δy) are kept up to a budget of rows; a run with more rows in its
//    windows takes the residuals in a second run of the rig (ConeResiduals), the same numbers.
//  - δy and δx against the tool's x for the plots, each a bounded sim::PlotPyramid.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "lathectl/sim/plot_pyramid.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/c_tracer/rig.hpp"

namespace lathectl::systems::c_tracer {

// The zone around a shoulder (a vertical step) where the rig masks δy and δx belongs to the
// shoulder: ±0.5 mm of the tool's x (rig.cpp, near_step).
constexpr double kShoulderZone_mm = 0.5;

struct FeatureErrors {
  double max_dx_um = 0.0, max_dy_um = 0.0;
  bool dx_defined = false;  // a finite δx in the feature's range (its zone for a shoulder)
};

// A cone's second half: the steady lag and the waviness.
struct ConeWindow {
  std::size_t feature = 0;  // index in the features
  double from_mm = 0.0, to_mm = 0.0;  // carriage x
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, n = 0.0;
  double last_lag_um = std::numeric_limits<double>::quiet_NaN();
  double k0 = 0.0, k1 = 0.0;  // δy's trend, after the run
  double lo = 1e300, hi = -1e300;
  std::vector<std::pair<double, double>> kept;  // (carriage x, δy) while within the budget
  bool complete = true;                         // every window row kept
  [[nodiscard]] bool in(double cx, double dy) const noexcept {
    return cx >= from_mm && cx <= to_mm && std::isfinite(dy);
  }
  void residual(double cx, double dy) noexcept {
    const double res = dy - (k0 + k1 * cx);
    lo = std::min(lo, res);
    hi = std::max(hi, res);
  }
  [[nodiscard]] double waviness_um() const noexcept { return n > 2 ? hi - lo : 0.0; }
};

class TracerMetrics final : public sim::RowSink {
 public:
  // Rows kept for the cones' residuals, over all cones (16 B each): 8 MB.
  static constexpr std::size_t kKeptRows = std::size_t{1} << 19;
  TracerMetrics(const sim::Recorder& rec, const std::vector<TracerFeature>& features,
                std::size_t kept_rows = kKeptRows);
  void row(std::span<const double> v) noexcept override;
  // After the run: the cones' trends, and their residuals from the kept rows. False when a cone
  // has more window rows than were kept: then feed a second run of the rig to residuals().
  bool finish();
  [[nodiscard]] sim::RowSink& residuals() noexcept { return second_; }

  [[nodiscard]] double max_dx_um() const noexcept { return max_dx_; }
  [[nodiscard]] double max_dy_um() const noexcept { return max_dy_; }
  [[nodiscard]] bool any_dx() const noexcept { return any_dx_; }
  [[nodiscard]] double first_load_N() const noexcept { return first_load_; }
  [[nodiscard]] const std::vector<FeatureErrors>& features() const noexcept { return feat_; }
  [[nodiscard]] const std::vector<ConeWindow>& cones() const noexcept { return cones_; }
  // δy, δx against the tool's x [mm].
  [[nodiscard]] const sim::PlotPyramid& dy_along_x() const noexcept { return dy_x_; }
  [[nodiscard]] const sim::PlotPyramid& dx_along_x() const noexcept { return dx_x_; }

 private:
  class Second final : public sim::RowSink {  // the residuals, on a second run of the rig
   public:
    explicit Second(TracerMetrics& m) : m_(m) {}
    void row(std::span<const double> v) noexcept override;

   private:
    TracerMetrics& m_;
  };
  struct Range {
    double a, b;  // tool x [mm]
    bool shoulder;
  };
  std::size_t tx_, cx_, dx_, dy_, lag_, load_;
  std::vector<Range> ranges_;
  std::vector<double> shoulders_;
  std::vector<FeatureErrors> feat_;
  std::vector<ConeWindow> cones_;
  std::size_t kept_budget_, kept_ = 0, rows_ = 0;
  double max_dx_ = 0.0, max_dy_ = 0.0, first_load_ = std::numeric_limits<double>::quiet_NaN();
  bool any_dx_ = false;
  sim::PlotPyramid dy_x_, dx_x_;
  Second second_{*this};
};

}  // namespace lathectl::systems::c_tracer
