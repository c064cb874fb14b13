#pragma once
// System B's settings (seed 001): the twin-turret rig with its measurement chain and CNC module,
// and what the study runs besides (the comparison without modulation, a sweep over the feed).
// Every default is a member initialiser here or in the rig's RigConfig; the section reader
// (settings.cpp) reads the file's [part], [material], [tool], [cut], [spindle],
// [vibration_sensor], [power_sensor], [modulation] and [study] over them.

#include <array>
#include <memory>
#include <vector>

#include "lathectl/io/acceptance.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/b_chatter/rig_config.hpp"

namespace lathectl::systems::b_chatter {

// [acceptance]: what the cut must achieve (settings.cpp describes each key).
extern const std::array<io::CriterionKey, 2> kAcceptanceKeys;

struct Settings : io::SettingsOf<Settings> {
  RigConfig rig;
  bool compare = true;                        // [study] also run without modulation
  std::vector<double> sweep_feed_mm_per_rev;  // [study] feeds of the with/without sweep
  io::AcceptanceLimits acceptance{kAcceptanceKeys};  // [acceptance], or the defaults
};

// The section reader (settings.cpp): the settings from the file's tables.
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The section reader alone: what a component that only reads B's settings links (its
// lathectl_b_chatter_settings). The one place the system's letter is written.
inline constexpr io::Section kReadSection{"B", &read_settings, nullptr};
// The cross-checks that need the whole scenario (validate.cpp: the step against the part's chatter,
// the rig configured once as a probe).
void validate(const io::Scenario& sc);
// Reader and validation: the registry's entry.
inline constexpr io::Section kSection{kReadSection.system, &read_settings, &validate};

}  // namespace lathectl::systems::b_chatter
