#pragma once
// System E's settings: the rig's configuration (sim::RigEConfig: cutting process, drives,
// sensors, controller, faults) and the scenario's options (the controllers compared), read from
// a system-E scenario by kReadSection (what the HAL components link) and, for the program, by
// kSection (the same reader, then a probe of the rig). Defaults are the members' initialisers.

#include <memory>
#include <string>
#include <vector>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/e_adaptive/rig.hpp"

namespace lathectl::systems::e_adaptive {

using Mode = control::AdaptiveFeedController::Mode;

struct Settings : io::SettingsOf<Settings> {
  sim::RigEConfig rig;
  std::vector<Mode> compare_modes;  // [compare] controllers: extra runs overlaid in the report
};

// Reads system E's tables of a scenario (after its common part) into a Settings.
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The reader only (validate = nullptr): what a HAL component links. The registry's kSection
// (study.hpp) adds the rig's cross-checks.
extern const io::Section kReadSection;

// "force by feed + speed law (seed 004)", ...: a mode as reports name it.
std::string mode_name(Mode m);

}  // namespace lathectl::systems::e_adaptive
