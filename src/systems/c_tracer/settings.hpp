#pragma once
// System C (seed 002), the hydraulic tracer: its settings, as a scenario file gives them
// ([machine], [slide], [template], [model], [linear], [servo], [friction], [cutting];
// docs/scenario-reference.md). The defaults are the member initialisers (RigConfig): the
// reader keeps them for an absent key.

#include <array>
#include <memory>
#include <string>

#include "lathectl/io/acceptance.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/c_tracer/rig_config.hpp"

namespace lathectl::systems::c_tracer {

// [acceptance]: what the copied profile must achieve (settings.cpp describes each key).
extern const std::array<io::CriterionKey, 3> kAcceptanceKeys;

struct Settings : io::SettingsOf<Settings> {
  RigConfig rig;
  std::string compare;  // [model] compare: "", "linear" or "nonlinear", a second run overlaid
  io::AcceptanceLimits acceptance{kAcceptanceKeys};  // [acceptance], or the defaults
};

// Reads C's tables into Settings (the common part, [run], is read before).
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The section reader alone: what a component that only reads C's settings links (its
// lathectl_c_tracer_settings). The one place the system's letter is written.
inline constexpr io::Section kReadSection{"C", &read_settings, nullptr};
// The cross-checks that need the whole scenario (validate.cpp: the rig configured once as a probe).
void validate(const io::Scenario& sc);
// Reader and validation: the registry's entry.
inline constexpr io::Section kSection{kReadSection.system, &read_settings, &validate};

}  // namespace lathectl::systems::c_tracer
