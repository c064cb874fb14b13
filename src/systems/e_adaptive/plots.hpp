#pragma once
// System E's time-series plots: the controllers compared along the cut, and the main run's
// detail (force within the revolution, disturbances, the reason-code timeline).

#include <array>
#include <span>
#include <string>
#include <vector>

#include "lathectl/io/report.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/e_adaptive/metrics.hpp"

namespace lathectl::systems::e_adaptive {

// The channels the controllers are compared by, along the part, row by row as a streamed rig
// records (a RowSink: memory bounded whatever the run's length). The x axis is the distance along
// the part [mm]: z advanced within a pass, summed over the passes. The runs cut the same part with
// the same passes, so this axis lines up where each run meets the same depth step or hard spot,
// whatever its speed (the fixed run takes 2½ times as long).
class PathPlots final : public sim::RowSink {
 public:
  // The compared channels; kForceRev is the per-revolution mean of the true force parameter
  // (control::PerRevolutionMean, as the claims compute it).
  enum Which { kForceRev, kFeedRev, kSpeed, kSpeedOpt, kPower, kToolLife, kCount };
  explicit PathPlots(const sim::Recorder& rec);
  void row(std::span<const double> v) noexcept override;
  [[nodiscard]] const sim::PlotPyramid& along(Which w) const noexcept { return plots_[w]; }
  // The path against time (x = time [s], y = path [mm]), to place the time axis's markers.
  [[nodiscard]] const sim::PlotPyramid& path_of_time() const noexcept { return path_t_; }
  [[nodiscard]] double path_end() const noexcept { return path_; }
  [[nodiscard]] double last_time() const noexcept { return t_last_; }

 private:
  std::size_t t_, z_, pass_;
  std::array<std::size_t, kCount> ch_{};
  double path_ = 0.0, z_prev_ = 0.0, pass_prev_ = 0.0, t0_ = 0.0, t_last_ = 0.0;
  std::size_t n_ = 0;
  control::PerRevolutionMean f_rev_;
  std::size_t rpm_;
  std::array<sim::PlotPyramid, kCount> plots_;
  sim::PlotPyramid path_t_;
};

struct PlotRun {
  const sim::Recorder* rec = nullptr;  // streamed: its decimated plot per channel against time
  const PathPlots* path = nullptr;
  const MetricsAccumulator* acc = nullptr;
  const Metrics* m = nullptr;
  std::string label;
  bool speed_law = false;  // seed 004's V_opt is recorded
};

// Appends the plots; runs.front() is the main run, `mk` its events on its time axis.
void add_run_plots(io::Report& rep, const std::vector<PlotRun>& runs,
                   const std::vector<io::Marker>& mk, const std::string& pname,
                   const std::string& unit);

}  // namespace lathectl::systems::e_adaptive
