#pragma once
// System B's machine parameters: the one place control::ModulationMachine's parameters are
// derived from a scenario. Rig B and the LinuxCNC component lathectl_modfeed both call
// machine_params(); what a host adds (its periods, how the feed reaches the turret, the
// ceiling) is in Host, and the policy a host's choice implies is here: with the factor output
// the staircase may not rise above the program's F (S_max ≤ ceiling · S_p).

#include "lathectl/control/modulation_machine.hpp"
#include "systems/b_chatter/rig_config.hpp"

namespace lathectl::systems::b_chatter {

struct Settings;

// The CNC's module period (update()) and the vibration sensor's sample period (sense()) the
// machine is built for; a host runs them as close as its own step allows (Host).
inline constexpr double kModulePeriod_s = 1e-3;
inline constexpr double kSamplePeriod_s = 1e-4;

struct Host {
  double module_period_s = kModulePeriod_s;  // update()'s period, as the host runs it
  double sample_period_s = kSamplePeriod_s;  // sense()'s period, as the host runs it
  control::ModulationMachine::FeedOutput output = control::ModulationMachine::FeedOutput::Drives;
  double ceiling = 1.0;  // (Factor) the program's F over the mean feed to keep
};

// Throws sim::ConfigError (a std::invalid_argument) at the key or module parameter that
// decides it.
[[nodiscard]] control::ModulationMachine::Params machine_params(const RigConfig& cfg,
                                                                const Host& host);
[[nodiscard]] control::ModulationMachine::Params machine_params(const Settings& s,
                                                                const Host& host);

}  // namespace lathectl::systems::b_chatter
