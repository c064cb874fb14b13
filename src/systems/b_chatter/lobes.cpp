#include "systems/b_chatter/lobes.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "lathectl/core/parallel.hpp"
#include "lathectl/io/progress.hpp"
#include "systems/b_chatter/lobes_outputs.hpp"

namespace lathectl::systems::b_chatter {

namespace {
// Progress: the bisection speeds, then the chart's speeds (each speed about as costly).
class Ticker {
 public:
  Ticker(const LobesInput& in, io::Progress* progress)
      : progress_(progress),
        total_work_(static_cast<double>(in.sd_speeds) +
                    (in.chart_speeds >= 2 && in.chart_depths >= 2
                         ? static_cast<double>(in.chart_speeds)
                         : 0.0)) {}
  void operator()(const char* phase) {
    const std::size_t k = ++work_done_;
    if (progress_ && total_work_ > 0)
      progress_->update(static_cast<double>(k) / total_work_, phase);
  }

 private:
  io::Progress* progress_;
  double total_work_;
  std::atomic<std::size_t> work_done_{0};
};

// Semi-discretization at sd_speeds speeds by bisection, in parallel, with the chart's scheme
// (quintic interpolation, 7 steps per period of the modes that can chatter below `hi`).
void sd_limits(const LobesInput& in, Ticker& tick, LobesRun& r) {
  const auto& fd = r.fd;
  auto& sd_speed = r.sd_speed;
  auto& sd_depth = r.sd_depth;
  auto& fd_depth = r.fd_depth;
  sd_speed.resize(static_cast<std::size_t>(in.sd_speeds));
  sd_depth.resize(sd_speed.size());
  fd_depth.resize(sd_speed.size());
  for (std::size_t k = 0; k < sd_speed.size(); ++k) {
    sd_speed[k] = in.min_rpm + (in.max_rpm - in.min_rpm) * (static_cast<double>(k) + 0.5) /
                                   static_cast<double>(sd_speed.size());
    fd_depth[k] = dynamics::envelope_depth(fd, sd_speed[k]);
  }
  core::parallel_for(sd_speed.size(), [&](std::size_t k) {
    const double hi = std::isfinite(fd_depth[k]) ? 3.0 * fd_depth[k] : 100.0 * fd.critical_depth_m;
    if (!std::isfinite(hi)) {  // no lobe anywhere (every mode across the chip): nothing to bisect
      sd_depth[k] = std::numeric_limits<double>::infinity();
      tick("semi-discretization limits");
      return;
    }
    const dynamics::SdChartOptions o;
    const int m = dynamics::sd_steps_per_delay(in.modal, sd_speed[k], hi, o);
    sd_depth[k] =
        dynamics::sd_limit_depth(in.modal, sd_speed[k], hi, m, 1e-3, o.interpolation_order);
    tick("semi-discretization limits");
  });
  for (std::size_t k = 0; k < sd_speed.size(); ++k)
    if (std::isfinite(sd_depth[k]) && std::isfinite(fd_depth[k]))
      r.worst = std::max(r.worst, std::abs(sd_depth[k] / fd_depth[k] - 1.0));
}

// The SD stability chart: the SD map's unstable roots on a speed × depth grid, and its boundary
// against the frequency-domain envelope where that lies inside the chart.
void sd_chart(const LobesInput& in, Ticker& tick, LobesRun& r) {
  const auto& fd = r.fd;
  if (in.chart_speeds < 2 || in.chart_depths < 2 || !std::isfinite(fd.critical_depth_m)) return;
  dynamics::SdChartOptions o;
  o.steps_per_period = in.chart_steps_per_period;
  o.on_speed_done = [&](std::size_t, std::size_t) { tick("semi-discretization chart"); };
  const double top =
      in.chart_max_depth_m > 0.0 ? in.chart_max_depth_m : 4.0 * fd.critical_depth_m;
  r.chart = dynamics::sd_stability_chart(in.modal, in.min_rpm, in.max_rpm, in.chart_speeds, top,
                                         in.chart_depths, o);
  for (std::size_t i = 0; i < r.chart->speed_rpm.size(); ++i) {
    const double b_fd = dynamics::envelope_depth(fd, r.chart->speed_rpm[i]);
    const double b_sd = r.chart->boundary_depth_m[i];
    if (!std::isfinite(b_fd) || !std::isfinite(b_sd) || b_fd > 0.98 * top) continue;
    r.chart_worst = std::max(r.chart_worst, std::abs(b_sd / b_fd - 1.0));
    ++r.chart_compared;
  }
}

std::vector<AlongPart> along_part(const LobesInput& in) {
  std::vector<AlongPart> along;
  if (in.part)
    for (double x : in.part->positions_m) {
      const auto sys = lobes_system_at(in, x);
      const auto r = dynamics::frequency_domain_lobes(sys, in.min_rpm, in.max_rpm, in.max_lobes,
                                                      kFrequencyPoints);
      double lowest = std::numeric_limits<double>::infinity();
      for (const auto& l : r.lobes) lowest = std::min(lowest, l.minimum.depth_m);
      along.push_back({x, r.critical_depth_m, r.critical_chatter_Hz, lowest,
                       part_first_mode_Hz(*in.part, x), part_static_stiffness(*in.part, x)});
    }
  return along;
}

}  // namespace

LobesRun compute_lobes(const LobesInput& in, io::Progress* progress) {
  Ticker tick(in, progress);
  LobesRun r;
  r.fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes,
                                          kFrequencyPoints);
  sd_limits(in, tick, r);
  sd_chart(in, tick, r);
  r.along = along_part(in);
  r.pockets = recommend_pockets(r.fd, in);
  return r;
}

nlohmann::json run_lobes(const LobesInput& in, const std::filesystem::path& out_dir,
                         io::Progress* progress) {
  const LobesRun r = compute_lobes(in, progress);
  nlohmann::json j = lobes_json(in, r);
  write_lobes_outputs(in, r, j, out_dir);
  return j;
}

}  // namespace lathectl::systems::b_chatter
