// System E's cross-checks once the whole scenario is read: the rig configured once as a probe,
// its rejection reported at the key it names.
#include <algorithm>
#include <stdexcept>

#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::systems::e_adaptive {

void validate(const io::Scenario& sc) {
  Rig probe;
  RigConfig cfg = sc.get<Settings>().rig;
  if (cfg.stock.passes.empty() && !cfg.stock.blank_diameter_mm.empty()) {
    // A blank without passes (a program cuts it): the rig, which runs passes, is probed with
    // one along the blank at its first diameter — the cross-checks of the controller, axis,
    // spindle and sensor do not depend on where the pass goes.
    const auto& b = cfg.stock.blank_diameter_mm;
    cfg.stock.passes.push_back(
        {b.front().at_mm, std::max(b.back().at_mm, b.front().at_mm + 1.0), b.front().value});
  }
  try {
    probe.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.step_s * 4);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e);
  }
}

}  // namespace lathectl::systems::e_adaptive
