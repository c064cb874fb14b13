// System C's cross-checks once the whole scenario is read: the rig configured once as a probe,
// its rejection reported at the key it names.
#include <stdexcept>

#include "systems/c_tracer/rig.hpp"
#include "systems/c_tracer/settings.hpp"

namespace lathectl::systems::c_tracer {

void validate(const io::Scenario& sc) {
  Rig probe;
  probe.set_streamed(true);  // no columns: the probe records nothing
  try {
    probe.configure(sc.get<Settings>().rig, sc.run.step_s, sc.run.record_interval_s);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e);
  }
}

}  // namespace lathectl::systems::c_tracer
