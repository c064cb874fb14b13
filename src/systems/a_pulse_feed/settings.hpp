#pragma once
// System A (seed 000), the hydraulic feed slide with pulse regulation: its settings, as a scenario
// file gives them ([machine], [part], [regulator], [eccentric], [slide], [sensor], [controller],
// [compare], [sweep], [metrics], [[fault]]; docs/scenario-reference.md). The defaults are the
// member initialisers (here and in sim::RigAConfig): the reader keeps them for an absent key.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lathectl/io/scenario.hpp"
#include "systems/a_pulse_feed/rig.hpp"

namespace lathectl::systems::a_pulse_feed {

// A second run of the same scenario with something swapped, overlaid in the report.
struct Comparison {
  std::string label;
  std::optional<sim::ControllerKind> controller;
  std::optional<sim::RegulatorKind> regulator;
};

struct Settings : io::SettingsOf<Settings> {
  sim::RigAConfig rig;
  std::optional<Comparison> compare;               // [compare]
  std::vector<double> sweep_leak_estimate_factor;  // [sweep]: controller K_leak / true K_leak
};

// Reads A's tables into Settings (the common part, [run], is read before).
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The section reader alone (no rig probe): what a component that only reads A's settings links.
extern const io::Section kReadSection;
// Reader and validation (the rig configured once as a probe): the registry's entry.
extern const io::Section kSection;

std::string controller_kind_name(sim::ControllerKind k);
std::string regulator_kind_name(sim::RegulatorKind k);

}  // namespace lathectl::systems::a_pulse_feed
