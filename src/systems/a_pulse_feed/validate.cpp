// System A's cross-checks once the whole scenario is read: the rig configured once as a probe,
// its rejection reported at the key it names.
#include <algorithm>
#include <stdexcept>

#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"

namespace lathectl::systems::a_pulse_feed {

void validate(const io::Scenario& sc) {
  Rig probe;
  try {
    probe.configure(sc.get<Settings>().rig, sc.run.step_s, sc.run.record_interval_s,
                    std::min(sc.run.duration_s, sc.run.step_s * 4));
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e);
  }
}

}  // namespace lathectl::systems::a_pulse_feed
