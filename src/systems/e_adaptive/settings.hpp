#pragma once
// System E's settings: the rig's configuration (RigConfig: cutting process, drives,
// sensors, controller, faults) and the scenario's options (the controllers compared), read from
// a system-E scenario by kReadSection (what the HAL components link) and, for the program, by
// kSection (the same reader, then a probe of the rig). Defaults are the members' initialisers.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "lathectl/io/acceptance.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/e_adaptive/rig_config.hpp"

namespace lathectl::systems::e_adaptive {

using Mode = control::AdaptiveFeedController::Mode;

// [cost]: what a part costs a production engineer: machine time at the machine-hour
// rate plus the share of a cutting edge used, each edge costing its price and the machine time
// of its change. cost = cycle/3600·rate + life_used·(edge + change_min/60·rate).
struct Cost {
  double machine_rate_per_h = 60.0;  // machine-hour rate (with operator and overhead)
  double tool_edge_cost = 3.0;       // one cutting edge: an indexable carbide insert / its edges
  double tool_change_min = 1.0;      // machine time to index or change the edge
};

// [chatter] (optional): what `lathectl optimize` needs for each piece's chatter margin (see
// docs/optimize.md): the tool's modes and the part as system B models it, a pinned-pinned
// Euler–Bernoulli beam between two centres (dynamics/beam.hpp), whose diameter the optimiser
// takes from the stock as the passes leave it. The rig does not read it.
struct Chatter {
  std::vector<dynamics::Mode> tool_modes;  // [[chatter.mode]]
  // [chatter] machine_file: a machine file of `lathectl lobes` (its path as read, relative to the
  // scenario's folder) whose [[mode]]s and fitted [[frf]] modes are the tool's too; `optimize`
  // reads it (system B's reader), at_key says where the scenario names it for its errors.
  std::string machine_file;
  std::string machine_file_at_key;
  bool part = false;                       // [chatter.part] given
  dynamics::BeamPart beam;                 // length = headstock_at − tailstock_at; diameter unused
  int part_modes = 3;
  double tailstock_at_mm = 0.0;  // stock z of the centres (z = 0 is the part's face)
  double headstock_at_mm = 0.0;
  [[nodiscard]] bool enabled() const {
    return part || !tool_modes.empty() || !machine_file.empty();
  }
};

// [acceptance]: what the part must achieve (settings.cpp describes each key).
extern const std::array<io::CriterionKey, 3> kAcceptanceKeys;

struct Settings : io::SettingsOf<Settings> {
  RigConfig rig;
  std::vector<Mode> compare_modes;  // [compare] controllers: extra runs overlaid in the report
  Cost cost;                        // [cost]
  // [sweep] planned_depth_mm: the tool-life verdict against the planned depth t_p, for the seed
  // law (exact from the main run: it never reads t_p) and the depth-corrected law (one run each).
  std::vector<double> sweep_planned_depth_mm;
  Chatter chatter;  // [chatter]
  io::AcceptanceLimits acceptance{kAcceptanceKeys};  // [acceptance], or the defaults
};

// Reads system E's tables of a scenario (after its common part) into a Settings.
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The section reader alone (validate = nullptr): what a HAL component links (its
// lathectl_e_adaptive_settings). The one place the system's letter is written.
inline constexpr io::Section kReadSection{"E", &read_settings, nullptr};
// The cross-checks that need the whole scenario (validate.cpp: the rig configured once as a probe).
void validate(const io::Scenario& sc);
// Reader and validation: the registry's entry.
inline constexpr io::Section kSection{kReadSection.system, &read_settings, &validate};

// Switches the controller to the depth-corrected speed law V·(t_p/t̂)^{x_v} at e.planned_depth_mm:
// x_v from the material's range containing S_p, the depth estimate from the handbook law of the
// measured force (Pz or Py) at the nominal strength.
void use_depth_corrected_law(RigConfig& e);

// "force by feed + speed law (seed 004)", ...: a mode as reports name it.
std::string mode_name(Mode m);

}  // namespace lathectl::systems::e_adaptive
