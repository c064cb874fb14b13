#pragma once
// System A (seed 000), the hydraulic feed slide with pulse regulation: its settings, as a scenario
// file gives them ([machine], [part], [regulator], [eccentric], [slide], [sensor], [controller],
// [compare], [sweep], [metrics], [[fault]]; docs/scenario-reference.md). The defaults are the
// member initialisers (here and in RigConfig): the reader keeps them for an absent key.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lathectl/io/acceptance.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/a_pulse_feed/rig_config.hpp"

namespace lathectl::systems::a_pulse_feed {

// A second run of the same scenario with something swapped, overlaid in the report.
struct Comparison {
  std::string label;
  std::optional<ControllerKind> controller;
  std::optional<RegulatorKind> regulator;
};

// [tolerance]: manufacturing errors (normal, σ each) drawn for a Monte Carlo of the mean flow of
// the pulsed regulator at its scenario setting and of a continuous throttle set for the same
// flow (advantage 5 of the seed: "far less manufacturing precision").
struct ToleranceStudy {
  std::size_t samples = 400;    // regulators drawn
  double slot_sigma_m = 1e-6;   // slot / gap opening error (both)
  double diameter_sigma_m = 5e-6;
  double mu_sigma = 0.03;       // relative
  double lap_sigma_m = 5e-6;    // overlap (pulsed only)
  double switching_sigma = 0.2; // relative, opening and closing times (pulsed only)
  double flow_tolerance = 0.05; // relative flow error a sample may make
};

// [acceptance]: what the cut must achieve (settings.cpp describes each key).
extern const std::array<io::CriterionKey, 3> kAcceptanceKeys;

struct Settings : io::SettingsOf<Settings> {
  RigConfig rig;
  std::optional<Comparison> compare;               // [compare]
  std::vector<double> sweep_leak_estimate_factor;  // [sweep]: controller K_leak / true K_leak
  std::vector<double> obliteration_removal;        // [obliteration_study] removal_per_stroke
  std::vector<double> obliteration_layer_m;        // [obliteration_study] layer_um (at η = 0)
  std::optional<ToleranceStudy> tolerance;         // [tolerance]
  io::AcceptanceLimits acceptance{kAcceptanceKeys};  // [acceptance], or the defaults
};

// Reads A's tables into Settings (the common part, [run], is read before).
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The section reader alone: what a component that only reads A's settings links (its
// lathectl_a_pulse_feed_settings). The one place the system's letter is written.
inline constexpr io::Section kReadSection{"A", &read_settings, nullptr};
// The cross-checks that need the whole scenario (validate.cpp: the rig configured once as a probe).
void validate(const io::Scenario& sc);
// Reader and validation: the registry's entry.
inline constexpr io::Section kSection{kReadSection.system, &read_settings, &validate};

std::string controller_kind_name(ControllerKind k);
std::string regulator_kind_name(RegulatorKind k);

}  // namespace lathectl::systems::a_pulse_feed
