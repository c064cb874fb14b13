#include "systems/e_adaptive/plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include "lathectl/control/types.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/sim/per_revolution.hpp"

namespace lathectl::systems::e_adaptive {

using io::Marker;
using io::Plot;
using io::Series;

namespace {

constexpr const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};

// Distance along the part [mm]: z advanced within a pass, summed over the passes. The
// runs cut the same part with the same passes, so this axis lines up where each run meets the
// same depth step or hard spot, whatever its speed (the fixed run takes 2½ times as long).
std::vector<double> cut_path_mm(const sim::Recorder& rec) {
  const auto z = rec.column("z_mm");
  const auto pass = rec.column("pass");
  std::vector<double> path(z.size(), 0.0);
  for (std::size_t i = 1; i < z.size(); ++i) {
    const bool same_pass = pass[i] == pass[i - 1];  // not the return to the next pass's start
    path[i] = path[i - 1] + (same_pass ? std::max(z[i] - z[i - 1], 0.0) : 0.0);
  }
  return path;
}

// The path position at time t of the run whose time axis is `t` (first sample at or after t).
double path_at(const std::vector<double>& t, const std::vector<double>& path, double at) {
  const auto it = std::lower_bound(t.begin(), t.end(), at);
  if (it == t.end()) return path.empty() ? std::nan("") : path.back();
  return path[static_cast<std::size_t>(it - t.begin())];
}

Series along_time(const PlotRun& r, const char* channel, const std::string& name,
                  const char* color) {
  return Series{name, io::column(*r.rec, "time_s"), io::column(*r.rec, channel), color, false,
                false};
}

}  // namespace

void add_run_plots(io::Report& rep, const std::vector<PlotRun>& runs, const std::vector<Marker>& mk,
                   const std::string& pname, const std::string& unit) {
  const PlotRun& main = runs.front();
  const std::vector<double> t_main = io::column(*main.rec, "time_s");
  const std::vector<double> path_main = cut_path_mm(*main.rec);
  std::vector<Marker> mk_path;
  for (const Marker& m : mk) mk_path.push_back({path_at(t_main, path_main, m.x), m.label});

  const auto along_path = [&](const PlotRun& r, const char* channel, const std::string& name,
                              const char* color, bool per_rev) {
    Series s = along_time(r, channel, name, color);
    if (per_rev) {  // the per-revolution mean, as the claims compute it
      const double dt = s.x.size() > 1 ? s.x[1] - s.x[0] : 1.0;
      s.y = sim::per_revolution_mean(s.y, r.rec->column("spindle_rpm"), dt);
    }
    s.x = cut_path_mm(*r.rec);
    return s;
  };
  const std::string x_path = "distance along the part [mm] (all passes)";
  double path_end = 0.0;
  for (const PlotRun& r : runs) {
    const auto p = cut_path_mm(*r.rec);
    if (!p.empty()) path_end = std::max(path_end, p.back());
  }
  // Every run's channel along the part (per_rev: its per-revolution mean).
  const auto compared = [&](std::string title, std::string y_label, const char* channel,
                            bool per_rev) {
    Plot p{std::move(title), x_path, std::move(y_label), {}, mk_path};
    p.x_min = 0.0;
    p.x_max = path_end;
    for (std::size_t i = 0; i < runs.size(); ++i)
      p.series.push_back(along_path(runs[i], channel, runs[i].label, kColors[i % 4], per_rev));
    return p;
  };
  const std::string suffix = runs.size() > 1 ? ", the controllers along the cut" : "";

  Plot force = compared("Per-revolution " + pname + " (the feed's reach) and its limit" + suffix,
                        pname + " [" + unit + "]", "force_parameter_true", true);
  force.series.push_back(
      {"limit", {0.0, path_end}, {main.m->force_limit, main.m->force_limit}, "#555", true, false});
  rep.plots.push_back(force);
  rep.plots.push_back(compared("Feed per revolution (chip thickness)" + suffix, "feed [mm/rev]",
                               "feed_per_rev_mm", false));
  Plot speed = compared("Cutting speed V (sensor 20) and seed 004's V_opt" + suffix,
                        "speed [m/min]", "speed_m_per_min", false);
  if (main.speed_law) {
    Series vo = along_path(main, "speed_opt_m_per_min", "V_opt, " + main.label, kColors[0], false);
    vo.dashed = true;
    speed.series.push_back(vo);
  }
  rep.plots.push_back(speed);
  rep.plots.push_back(
      compared("Spindle electrical power" + suffix, "power [kW]", "spindle_power_kW", false));
  Plot life =
      compared("Tool life used (∫ dt/T)" + suffix, "share of one edge", "tool_life_used", false);
  // The plan, t / T_plan, at the main run's pace.
  Series plan{"plan: t / T_plan (main run's time)", path_main, t_main, "#555", true, false};
  for (double& v : plan.y) v = v / 60.0 / main.m->tool_life_planned_min;
  life.series.push_back(plan);
  rep.plots.push_back(life);

  // The main run in detail, on its own time axis.
  const double t_end = t_main.empty() ? 1.0 : t_main.back();
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
      {"limit", {0.0, t_end}, {main.m->force_limit, main.m->force_limit}, "#1f2328", true, false});
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
  std::set<int> codes;
  for (const double c : reason.series.front().y)
    if (std::isfinite(c)) codes.insert(static_cast<int>(c));
  for (const int c : codes)
    reason.lanes.push_back({static_cast<double>(c),
                            std::string(control::reason_name(static_cast<control::Reason>(c))) +
                                " (" + std::to_string(c) + ")"});
  rep.plots.push_back(reason);
}

}  // namespace lathectl::systems::e_adaptive
