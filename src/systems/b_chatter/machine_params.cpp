#include "systems/b_chatter/machine_params.hpp"

#include <algorithm>

#include "lathectl/sim/config_error.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl::systems::b_chatter {

control::ModulationMachine::Params machine_params(const RigConfig& cfg, const Host& host) {
  using FeedOutput = control::ModulationMachine::FeedOutput;
  control::ModulationMachine::Params mp{cfg.vibration, cfg.power, cfg.module};
  mp.vibration.sample_period_s = host.sample_period_s;
  mp.module.period_s = host.module_period_s;
  mp.output = host.output;
  if (host.output == FeedOutput::Factor) {
    if (!(host.ceiling >= 1.0 && host.ceiling <= 100.0))
      throw sim::ConfigError("ceiling", "expected 1 … 100");
    mp.ceiling = host.ceiling;
    // LinuxCNC clips the factor at 1: the staircase may not rise above the program's F.
    mp.module.s_max_fraction = std::min(mp.module.s_max_fraction, host.ceiling);
    if (!(mp.module.s_max_fraction > 1.0))
      throw sim::ConfigError("ceiling",
                             "ceiling must exceed 1 for the staircase to rise above the mean");
  }
  return mp;
}

control::ModulationMachine::Params machine_params(const Settings& s, const Host& host) {
  return machine_params(s.rig, host);
}

}  // namespace lathectl::systems::b_chatter
