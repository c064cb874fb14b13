// System E's cost before it runs (`lathectl check`; lathectl/io/estimate.hpp): its study's
// runs, counted as study.cpp makes them, times the cost per step measured on the examples.
#include <algorithm>

#include "systems/e_adaptive/entry.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::systems::e_adaptive {

namespace {
constexpr io::StepCosts kCosts{0.80e-6, 180.0};
}  // namespace

io::RunEstimate estimate(const io::Scenario& sc) {
  io::RunEstimate e = io::report_only();
  const auto& s = sc.get<Settings>();
  double modes = 1.0;
  for (const auto m : s.compare_modes)
    if (m != s.rig.controller.mode) modes += 1.0;
  // The main run and the comparisons (two at a time), then the planned-depth sweep (one run per
  // depth and maybe the seed law's), each at most run.duration_s (the part may end sooner).
  io::add_rig_runs(e, sc, modes, 2.0, kCosts, std::min(modes, 2.0));
  if (!s.sweep_planned_depth_mm.empty())
    io::add_rig_runs(e, sc, static_cast<double>(s.sweep_planned_depth_mm.size()) + 1.0, 2.0, kCosts,
                     0.0);
  e.breakdown += " (a run ends with the part: upper bounds)";
  e.upper_bound = true;
  return e;
}

}  // namespace lathectl::systems::e_adaptive
