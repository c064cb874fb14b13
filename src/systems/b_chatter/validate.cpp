// System B's cross-checks once the whole scenario is read: the rig configured once as a probe.
#include <stdexcept>

#include "lathectl/io/format.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl::systems::b_chatter {

void validate(const io::Scenario& sc) {
  const RigConfig& b = sc.get<Settings>().rig;
  try {
    // Like A, C, D and E: refuse a step too coarse for the dynamics (here the chatter).
    double f_Hz = 0.0;
    const double max_step = Rig::max_step_s(b, &f_Hz);
    if (sc.run.step_s > max_step)
      sc.keys->fail("run.step_s", "too coarse for the part's chatter near " +
                                      io::fmt(f_Hz, "%.0f") + " Hz (ω·dt ≤ 0.2): use step_s ≤ " +
                                      io::fmt(max_step, "%.3g") + " s");
    Rig probe;
    probe.configure(b, sc.run.step_s, sc.run.record_interval_s, sc.run.step_s * 4);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e);
  }
}

}  // namespace lathectl::systems::b_chatter
