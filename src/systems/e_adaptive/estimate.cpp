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
  const Mode main = s.rig.controller.mode;
  double modes = 1.0;
  bool prior = main == Mode::ForceFeed, seed = main == Mode::ForceFeedSpeed;
  for (const auto m : s.compare_modes)
    if (m != main) {
      modes += 1.0;
      prior = prior || m == Mode::ForceFeed;
      seed = seed || m == Mode::ForceFeedSpeed;
    }
  // The main run and the comparisons (two at a time), then the runs beside them as study.cpp's
  // run_beside makes them (two at a time): the prior art at seed 004's tool budget (when both
  // are run, without faults), one run per planned depth, and the seed law's own when the main
  // run is not it — each at most run.duration_s (the part may end sooner).
  io::add_rig_runs(e, sc, modes, 2.0, kCosts, std::min(modes, 2.0));
  const bool main_seed_law = main == Mode::ForceFeedSpeed && s.rig.controller.depth_exponent_xv == 0.0;
  const double beside = (prior && seed && s.rig.faults.empty() ? 1.0 : 0.0) +
                        static_cast<double>(s.sweep_planned_depth_mm.size()) +
                        ((!s.sweep_planned_depth_mm.empty() || s.rig.life_law) && !main_seed_law
                             ? 1.0
                             : 0.0);
  if (beside > 0.0) io::add_rig_runs(e, sc, beside, 2.0, kCosts, 0.0);
  e.breakdown += " (a run ends with the part: upper bounds)";
  e.upper_bound = true;
  return e;
}

}  // namespace lathectl::systems::e_adaptive
