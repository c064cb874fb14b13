#pragma once
// System A's machine parameters: the one place control::SlideMachine's parameters are derived
// from a scenario. Rig A and the LinuxCNC component lathectl_slide both call machine_params();
// what a host adds is in Host. The derived numbers are the controller's design model of the
// slide: the regulator's gain μπd·√(2Δp/ρ), the leakage and friction estimates, the compliance
// C_d + V/B, the sensor's K_UP and U_0, the modulation (AIM: the slot, FIM: the frequency) and
// the slot's limit at the regulator's.

#include "lathectl/control/slide_machine.hpp"
#include "systems/a_pulse_feed/rig_config.hpp"

namespace lathectl::systems::a_pulse_feed {

struct Settings;

// What a host adds to the scenario. A's machine takes nothing from its host (the control period
// is the scenario's controller.period_ms): a host only says what it runs.
struct Host {
  // The machine runs on a real machine's I/O (lathectl_slide): only a pulsed regulator under
  // AIM or FIM has the valve and the actuator it drives. false: the rig (any regulator, an
  // uncontrolled machine too).
  bool machine_io = false;
};

// The machine's parameters for the scenario's rig. Throws sim::ConfigError (a
// std::invalid_argument) at the scenario key that decides it.
[[nodiscard]] control::SlideMachine::Params machine_params(const RigConfig& cfg, const Host& host);
[[nodiscard]] control::SlideMachine::Params machine_params(const Settings& s, const Host& host);

// The force the machine starts from (SlideMachine::start): the programmed feed on the
// deterministic part of the blank at its start [N] — the rig's nominal force.
[[nodiscard]] double nominal_force_N(const RigConfig& cfg);

}  // namespace lathectl::systems::a_pulse_feed
