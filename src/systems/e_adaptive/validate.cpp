// System E's cross-checks once the whole scenario is read: the rig configured once as a probe,
// its rejection reported at the key it names.
#include <stdexcept>

#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::systems::e_adaptive {

void validate(const io::Scenario& sc) {
  Rig probe;
  try {
    probe.configure(sc.get<Settings>().rig, sc.run.step_s, sc.run.record_interval_s,
                    sc.run.step_s * 4);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e);
  }
}

}  // namespace lathectl::systems::e_adaptive
