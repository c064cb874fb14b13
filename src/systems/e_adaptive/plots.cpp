#include "systems/e_adaptive/plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include "lathectl/control/types.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/control/per_revolution.hpp"

namespace lathectl::systems::e_adaptive {

using io::Marker;
using io::Plot;
using io::Series;

PathPlots::PathPlots(const sim::Recorder& rec)
    : t_(rec.index("time_s")),
      z_(rec.index("z_mm")),
      pass_(rec.index("pass")),
      rpm_(rec.index("spindle_rpm")) {
  ch_[kForceRev] = rec.index("force_parameter_true");
  ch_[kFeedRev] = rec.index("feed_per_rev_mm");
  ch_[kSpeed] = rec.index("speed_m_per_min");
  ch_[kSpeedOpt] = rec.index("speed_opt_m_per_min");
  ch_[kPower] = rec.index("spindle_power_kW");
  ch_[kToolLife] = rec.index("tool_life_used");
}

void PathPlots::row(std::span<const double> v) noexcept {
  const std::size_t i = n_++;
  const double t = v[t_];
  if (i == 0) t0_ = t;
  t_last_ = t;
  if (i == 1) f_rev_.configure(t - t0_);  // the record interval, as MetricsAccumulator takes it
  // Not the return to the next pass's start.
  if (i > 0 && v[pass_] == pass_prev_) path_ += std::max(v[z_] - z_prev_, 0.0);
  z_prev_ = v[z_];
  pass_prev_ = v[pass_];
  for (std::size_t k = 0; k < kCount; ++k)
    plots_[k].push(path_, k == kForceRev ? f_rev_.push(v[ch_[k]], v[rpm_]) : v[ch_[k]]);
  path_t_.push(t, path_);
}

namespace {

constexpr const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};

// The path position at time `at` on the run's path-of-time points (first point at or after).
double path_at(const std::vector<double>& t, const std::vector<double>& path, double at) {
  const auto it = std::lower_bound(t.begin(), t.end(), at);
  if (it == t.end()) return path.empty() ? std::nan("") : path.back();
  return path[static_cast<std::size_t>(it - t.begin())];
}

Series along_time(const PlotRun& r, const char* channel, const std::string& name,
                  const char* color) {
  Series s{name, {}, {}, color, false, false};
  r.rec->plot_points(channel, s.x, s.y);
  s.pyramid = r.rec->plot_pyramid(channel);
  return s;
}

}  // namespace

void add_run_plots(io::Report& rep, const std::vector<PlotRun>& runs, const std::vector<Marker>& mk,
                   const std::string& pname, const std::string& unit) {
  const PlotRun& main = runs.front();
  std::vector<double> t_main, path_main;
  main.path->path_of_time().points(t_main, path_main);
  std::vector<Marker> mk_path;
  for (const Marker& m : mk) mk_path.push_back({path_at(t_main, path_main, m.x), m.label});

  const auto along_path = [&](const PlotRun& r, PathPlots::Which w, const std::string& name,
                              const char* color) {
    Series s{name, {}, {}, color, false, false};
    s.pyramid = r.path->along(w).finished();
    s.pyramid->points(s.x, s.y);
    return s;
  };
  const std::string x_path = "distance along the part [mm] (all passes)";
  double path_end = 0.0;
  for (const PlotRun& r : runs) path_end = std::max(path_end, r.path->path_end());
  // Every run's channel along the part.
  const auto compared = [&](std::string title, std::string y_label, PathPlots::Which w) {
    Plot p{std::move(title), x_path, std::move(y_label), {}, mk_path};
    p.x_min = 0.0;
    p.x_max = path_end;
    for (std::size_t i = 0; i < runs.size(); ++i)
      p.series.push_back(along_path(runs[i], w, runs[i].label, kColors[i % 4]));
    return p;
  };
  const std::string suffix = runs.size() > 1 ? ", the controllers along the cut" : "";

  Plot force = compared("Per-revolution " + pname + " (the feed's reach) and its limit" + suffix,
                        pname + " [" + unit + "]", PathPlots::kForceRev);
  force.series.push_back(
      {"limit", {0.0, path_end}, {main.m->load_limit, main.m->load_limit}, "#555", true, false});
  rep.plots.push_back(force);
  rep.plots.push_back(compared("Feed per revolution (chip thickness)" + suffix, "feed [mm/rev]",
                               PathPlots::kFeedRev));
  Plot speed = compared("Cutting speed V (sensor 20) and seed 004's V_opt" + suffix,
                        "speed [m/min]", PathPlots::kSpeed);
  if (main.speed_law) {
    Series vo = along_path(main, PathPlots::kSpeedOpt, "V_opt, " + main.label, kColors[0]);
    vo.dashed = true;
    speed.series.push_back(vo);
  }
  rep.plots.push_back(speed);
  rep.plots.push_back(
      compared("Spindle electrical power" + suffix, "power [kW]", PathPlots::kPower));
  Plot life =
      compared("Tool life used (∫ dt/T)" + suffix, "share of one edge", PathPlots::kToolLife);
  // The plan, t / T_plan, at the main run's pace.
  Series plan{"plan: t / T_plan (main run's time)", path_main, t_main, "#555", true, false};
  for (double& v : plan.y) v = v / 60.0 / main.m->tool_life_planned_min;
  life.series.push_back(plan);
  rep.plots.push_back(life);

  // The main run in detail, on its own time axis.
  const double t_end = main.path->last_time() > 0.0 ? main.path->last_time() : 1.0;
  const auto detail = [&](std::string title, std::string y_label) {
    Plot p{std::move(title), "time [s]", std::move(y_label), {}, mk};
    p.x_min = 0.0;
    p.x_max = t_end;
    return p;
  };
  // What the controller saw (sensor 4, noisy) underneath, the true value drawn over it.
  Plot raw = detail(pname + " within the revolution (runout of the eccentric blank), main run",
                    pname + " [" + unit + "]");
  raw.series.push_back(
      along_time(main, "force_parameter", "as the controller saw it (sensor 4)", "#c4c9d0"));
  raw.series.push_back(along_time(main, "force_parameter_true", "true", "#b45309"));
  raw.series.push_back(
      {"limit", {0.0, t_end}, {main.m->load_limit, main.m->load_limit}, "#1f2328", true, false});
  rep.plots.push_back(raw);

  Plot depth = detail("What the tool meets: depth of cut (main run)", "depth [mm]");
  depth.series.push_back(along_time(main, "depth_mm", "depth of cut", "#8c564b"));
  rep.plots.push_back(depth);
  Plot hard = detail("What the tool meets: hardness (main run)", "strength factor");
  hard.series.push_back(along_time(main, "strength_factor", "strength factor", "#9467bd"));
  rep.plots.push_back(hard);

  // The decisions as a timeline: one lane per reason code that occurs (names as in the
  // decisions table).
  Plot reason = detail("Reason code timeline, main run (codes in the decisions table)", "");
  reason.series.push_back(along_time(main, "reason_code", "", "#444"));
  // The codes the record holds: the decimated band's (each bucket's extremes) and every code the
  // accumulator counted (one held between a bucket's extremes too).
  std::set<int> codes;
  for (const double c : reason.series.front().y)
    if (std::isfinite(c)) codes.insert(static_cast<int>(c));
  for (const auto& span : main.acc->reasons()) codes.insert(span.code);
  for (const int c : codes)
    reason.lanes.push_back({static_cast<double>(c),
                            std::string(control::reason_name(static_cast<control::Reason>(c))) +
                                " (" + std::to_string(c) + ")"});
  rep.plots.push_back(reason);
}

}  // namespace lathectl::systems::e_adaptive
