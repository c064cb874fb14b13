#include "systems/estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/c_tracer/settings.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::systems {

namespace {

// CPU seconds per simulated step (per part and pass for D's linearised Monte Carlo) and bytes
// per recorded row of one run's channels CSV: fitted to the examples' `lathectl run` (user time on
// the 2-core CI machine, Debian 12, x86-64, -O2, 2026-11-26; docs/scenario-reference.md, "What a
// run costs").
struct Costs {
  double step_s;
  double row_bytes;
};
constexpr Costs kA{0.15e-6, 130.0};
constexpr Costs kB{0.40e-6, 130.0};
constexpr Costs kC{3.0e-6, 60.0};
constexpr Costs kE{0.80e-6, 180.0};
constexpr double kDFullStep = 0.40e-6;     // the full transducer model, per step of a part
constexpr double kDTripFraction = 0.2;     // a full-model part ends at the trip: about this share
                                           // of run.duration_s on the examples (a gauge that never
                                           // trips runs every part to run.duration_s)
constexpr double kDLinearPartPass = 6e-6;  // the linearised model, per part and pass
constexpr double kDPartRowBytes = 42.0;    // channels.csv of D: one row a part
constexpr double kReportBytes = 1.0e6;     // report.html and summary.json, about

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, v >= 1e5 ? "%.2g" : "%.0f", v);
  return b;
}

double cores() { return std::max(1u, std::thread::hardware_concurrency()); }

// `runs` rig runs of `steps` each, `parallel` of them at a time at most.
void rig_runs(RunEstimate& e, const io::Scenario& sc, double runs, double parallel, Costs c,
              double recorded_runs) {
  const double steps = std::ceil(sc.run.duration_s / sc.run.step_s);
  e.simulated_steps += runs * steps;
  const double cpu = runs * steps * c.step_s;
  e.cpu_s += cpu;
  e.wall_s += cpu / std::min({runs, parallel, cores()});
  e.output_bytes += recorded_runs * (sc.run.duration_s / sc.run.record_interval_s) * c.row_bytes;
  e.breakdown += (e.breakdown.empty() ? "" : "; ") + num(runs) + (runs == 1 ? " run" : " runs") +
                 " × " + num(steps) + " steps";
}

}  // namespace

std::string duration_text(double s, bool upper_bound) {
  const char* q = upper_bound ? "at most" : "about";
  char b[48];
  if (s < 1.0)
    std::snprintf(b, sizeof b, "under a second");
  else if (s < 100.0)
    std::snprintf(b, sizeof b, "%s %.0f s", q, s);
  else if (s < 3600.0)
    std::snprintf(b, sizeof b, "%s %.0f min", q, s / 60.0);
  else if (s < 48.0 * 3600.0)
    std::snprintf(b, sizeof b, "%s %.1f h", q, s / 3600.0);
  else
    std::snprintf(b, sizeof b, "%s %.0f days", q, s / 86400.0);
  return b;
}

std::string size_text(double bytes, bool upper_bound) {
  const char* q = upper_bound ? "at most" : "about";
  char b[48];
  if (bytes < 1e6)
    std::snprintf(b, sizeof b, "%s %.0f kB", q, bytes / 1e3);
  else if (bytes < 1e9)
    std::snprintf(b, sizeof b, "%s %.0f MB", q, bytes / 1e6);
  else
    std::snprintf(b, sizeof b, "%s %.1f GB", q, bytes / 1e9);
  return b;
}

std::string summary_text(const RunEstimate& e) {
  return e.breakdown + "; " + duration_text(e.cpu_s, e.upper_bound) + " of CPU (" +
         duration_text(e.wall_s, e.upper_bound) + " on " + num(cores()) + " cores); output " +
         size_text(e.output_bytes, e.upper_bound);
}

RunEstimate estimate(const io::Scenario& sc) {
  RunEstimate e;
  e.output_bytes = kReportBytes;
  if (sc.system == "A") {
    const auto& s = sc.get<a_pulse_feed::Settings>();
    const double cmp = s.compare ? 1.0 : 0.0;
    // The main run, its comparison and one run per K_leak factor, one after another.
    rig_runs(e, sc, 1.0 + cmp + static_cast<double>(s.sweep_leak_estimate_factor.size()), 1.0,
             kA, 1.0 + cmp);
  } else if (sc.system == "B") {
    const auto& s = sc.get<systems::b_chatter::Settings>();
    const bool modulated = s.rig.source != control::ModulationSource::None;
    const double main = modulated && s.compare ? 2.0 : 1.0;
    rig_runs(e, sc, main, 2.0, kB, main);
    if (!s.sweep_feed_mm_per_rev.empty())  // with and without modulation at each feed, 4 at a time
      rig_runs(e, sc, (modulated ? 2.0 : 1.0) * static_cast<double>(s.sweep_feed_mm_per_rev.size()),
               4.0, kB, 0.0);
  } else if (sc.system == "C") {
    const auto& s = sc.get<c_tracer::Settings>();
    const double runs = s.compare.empty() ? 1.0 : 2.0;
    // C traces the whole template whatever run.duration_s says: its length at the feed speed.
    io::Scenario traced = sc;
    const auto& r = s.rig;
    const double v = r.feed_m_per_rev * r.spindle_rpm / 60.0;
    if (v > 0.0 && r.profile.xs().size() >= 2)
      traced.run.duration_s = (r.profile.xs().back() - r.profile.xs().front()) / v;
    rig_runs(e, traced, runs, 1.0, kC, runs);
  } else if (sc.system == "D") {
    const auto& s = sc.get<systems::d_gauging::Settings>();
    // Full model: the recorded part, the one without noise, the noisy parts and (calibrated_
    // dynamic) up to calibration_parts_max more, each at most run.duration_s long, on all cores.
    const double full = 2.0 + static_cast<double>(s.full_parts) +
                        (s.threshold == "calibrated_dynamic"
                             ? static_cast<double>(s.calibration_parts_max)
                             : 0.0);
    const double steps = std::ceil(sc.run.duration_s / sc.run.step_s);
    e.simulated_steps = full * steps;
    const double full_cpu = full * steps * kDTripFraction * kDFullStep;
    // Linearised: the calibration's parts and the Monte Carlo's, three passes over each.
    const double linear = 2.0 * static_cast<double>(s.parts);
    const double linear_cpu = 3.0 * linear * kDLinearPartPass;
    e.parts = linear / 2.0 + static_cast<double>(s.full_parts);
    e.cpu_s = full_cpu + linear_cpu;
    e.wall_s = e.cpu_s / cores();
    e.output_bytes += static_cast<double>(s.parts) * kDPartRowBytes +
                      (sc.run.duration_s / sc.run.record_interval_s) * 120.0;
    e.breakdown = num(static_cast<double>(s.parts)) + " linearised parts; " + num(full) +
                  " full-model parts × up to " + num(steps) + " steps (about a fifth of that "
                  "when the gauge trips)";
  } else if (sc.system == "E") {
    const auto& s = sc.get<e_adaptive::Settings>();
    double modes = 1.0;
    for (const auto m : s.compare_modes)
      if (m != s.rig.controller.mode) modes += 1.0;
    // The main run and the comparisons (two at a time), then the planned-depth sweep (one run per
    // depth and maybe the seed law's), each at most run.duration_s (the part may end sooner).
    rig_runs(e, sc, modes, 2.0, kE, std::min(modes, 2.0));
    if (!s.sweep_planned_depth_mm.empty())
      rig_runs(e, sc, static_cast<double>(s.sweep_planned_depth_mm.size()) + 1.0, 2.0, kE, 0.0);
    e.breakdown += " (a run ends with the part: upper bounds)";
    e.upper_bound = true;
  }
  return e;
}

}  // namespace lathectl::systems
