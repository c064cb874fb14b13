#pragma once
// System D's machine side from a scenario: the one place control::GaugeMachine::Params are derived
// from the settings. The gauging rig (every part of every study) and the LinuxCNC component
// lathectl_gauge both call machine_params(); what differs between them is only what a host adds
// (MachineHost), never a policy of its own.

#include <limits>

#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl::systems::d_gauging {

// What a host adds. The defaults are the rig's.
struct MachineHost {
  // The machine side's period [s]; NaN: the transducer's step (the rig runs them together).
  double period_s = std::numeric_limits<double>::quiet_NaN();
  // The host's x [m] of the target size (a machine's X); NaN: the process's own coordinate.
  double target_x_m = std::numeric_limits<double>::quiet_NaN();
  // How far short of the backstop a plunge toward it counts as there [m] (a trajectory
  // planner's rounding of the programmed position).
  double backstop_tolerance_m = 0.0;
  // Signal lost below this fraction of the free signal for a whole window; 0: not checked
  // (a simulated part's wire does not break).
  double signal_lost = 0.0;
  // How long the host's axis goes on at the old feed after a command [s] (LinuxCNC: motion reads
  // the gauge's outputs in its next servo period, and the position comes back periods later).
  // The relay's response is shortened by it, so a command takes effect t_r after its crossing as
  // in the rig (whose stop is immediate: 0). At most t_r.
  double stop_latency_s = 0.0;
};

// The cycle's steps before size for a sequence on `line` (gauging_cycle), with the delay the
// study and the machine both read between a crossing and the feed's change: the filter's lag,
// the relay's response and the bridges' lag. Throws std::invalid_argument as gauging_cycle.
[[nodiscard]] GaugingCycle cycle_for(const sensors::VibroContactGauge::Params& transducer,
                                     const Sequence& s, const design::GaugeLine& line,
                                     const GaugingProcess& p, double size_threshold_V);

// The machine side of process p on transducer g (configured on its step) with the size step's
// threshold [V]: p's cycle, then size; armed once the filter has settled on the first contact.
[[nodiscard]] control::GaugeMachine::Params machine_params(const GaugingProcess& p,
                                                          const sensors::VibroContactGauge& g,
                                                          double threshold_V,
                                                          const MachineHost& host = {});

}  // namespace lathectl::systems::d_gauging
