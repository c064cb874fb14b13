// System A's cost before it runs (`lathectl check`; lathectl/io/estimate.hpp): its study's
// runs, counted as study.cpp makes them, times the cost per step measured on the examples.
#include <cmath>

#include "systems/a_pulse_feed/entry.hpp"
#include "systems/a_pulse_feed/settings.hpp"

namespace lathectl::systems::a_pulse_feed {

namespace {
constexpr io::StepCosts kCosts{0.15e-6, 130.0};
// A step of the regulator alone (hydraulics::PulseRegulator, Throttle), as the regulator studies
// step it: fitted to a_regulator_switching with [tolerance] samples = 20000 and a_obliteration
// over 4 h at 200 Hz (lathectl run's user time, this machine, 2026-12-06).
constexpr double kRegulatorStep_s = 14e-9;

// The regulator studies beside the runs (regulator_studies.cpp), one after another: the
// tolerance Monte Carlo (6 draws of `samples` regulators, 6 periods of 100 steps each) and the
// obliteration study (the throttle, each η, each layer's pulsed and throttle pair, a quarter
// pulse period a step over the run). The characteristic study (about 6e5 steps, 10 ms) is left
// out: it does not grow with the scenario.
void add_regulator_studies(io::RunEstimate& e, const io::Scenario& sc, const Settings& s) {
  if (s.rig.regulator_kind != RegulatorKind::Pulsed) return;
  double steps = 0.0;
  if (s.tolerance) {
    const double tol = 6.0 * static_cast<double>(s.tolerance->samples) * 600.0;
    steps += tol;
    e.breakdown += "; tolerance study " + io::count_text(tol) + " regulator steps";
  }
  const bool against_throttle =
      s.compare && s.compare->regulator.value_or(s.rig.regulator_kind) == RegulatorKind::Throttle;
  if (!s.obliteration_removal.empty() && against_throttle) {
    const double runs = 1.0 + static_cast<double>(s.obliteration_removal.size()) +
                        2.0 * static_cast<double>(s.obliteration_layer_m.size());
    const double per_run = std::ceil(sc.run.duration_s / (0.25 / s.rig.frequency_Hz));
    steps += runs * per_run;
    e.breakdown += "; obliteration study " + io::count_text(runs) + " regulators × " +
                   io::count_text(per_run) + " steps";
  }
  e.cpu_s += steps * kRegulatorStep_s;
  e.wall_s += steps * kRegulatorStep_s;  // on one core, after the runs
}
}  // namespace

io::RunEstimate estimate(const io::Scenario& sc) {
  io::RunEstimate e = io::report_only();
  const auto& s = sc.get<Settings>();
  const double cmp = s.compare ? 1.0 : 0.0;
  // The main run, its comparison and one run per K_leak factor, one after another.
  io::add_rig_runs(e, sc, 1.0 + cmp + static_cast<double>(s.sweep_leak_estimate_factor.size()), 1.0,
                   kCosts, 1.0 + cmp);
  add_regulator_studies(e, sc, s);
  return e;
}

}  // namespace lathectl::systems::a_pulse_feed
