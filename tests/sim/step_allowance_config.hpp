#pragma once
// The LinuxCNC sample part (examples/linuxcnc/step_allowance.toml: a stepped allowance with a
// collar) as rig E's configuration, with a noiseless force sensor: the fixture of the tests of
// the stock model and of the feed-forward that reads it.

#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl::fixtures {

inline systems::e_adaptive::RigConfig step_allowance_config() {
  static const io::MaterialLibrary lib =
      io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  const auto sc =
      systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  auto cfg = sc.get<systems::e_adaptive::Settings>().rig;
  cfg.force_sensor.noise_sigma = 0.0;
  return cfg;
}

}  // namespace lathectl::fixtures
