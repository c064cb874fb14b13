// System A's cost before it runs (`lathectl check`; lathectl/io/estimate.hpp): its study's
// runs, counted as study.cpp makes them, times the cost per step measured on the examples.
#include "systems/a_pulse_feed/entry.hpp"
#include "systems/a_pulse_feed/settings.hpp"

namespace lathectl::systems::a_pulse_feed {

namespace {
constexpr io::StepCosts kCosts{0.15e-6, 130.0};
}  // namespace

io::RunEstimate estimate(const io::Scenario& sc) {
  io::RunEstimate e = io::report_only();
  const auto& s = sc.get<Settings>();
  const double cmp = s.compare ? 1.0 : 0.0;
  // The main run, its comparison and one run per K_leak factor, one after another.
  io::add_rig_runs(e, sc, 1.0 + cmp + static_cast<double>(s.sweep_leak_estimate_factor.size()), 1.0,
                   kCosts, 1.0 + cmp);
  return e;
}

}  // namespace lathectl::systems::a_pulse_feed
