#pragma once
// Scenario files (TOML): a system, a machine, a material, a part and its disturbances, a
// controller and its settings, run length and step. Shop units in key names; converted to SI
// here. Unknown keys, missing keys, wrong types and out-of-range values are InputErrors naming
// file, line and key. Nothing runs on a half-read scenario: parsing builds the whole Scenario
// or throws.

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/sim/gauging.hpp"
#include "lathectl/sim/rig_a.hpp"
#include "lathectl/sim/rig_b.hpp"
#include "lathectl/sim/rig_c.hpp"
#include "lathectl/sim/rig_e.hpp"

namespace lathectl::io {

struct RunSettings {
  double duration_s = 10.0;
  double step_s = 1e-4;
  double record_interval_s = 2e-3;
  std::uint64_t seed = 1;
};

// A second run of the same scenario with something swapped, overlaid in the report.
struct Comparison {
  std::string label;
  std::optional<sim::ControllerKind> controller;
  std::optional<sim::RegulatorKind> regulator;
};

struct Scenario {
  std::string file;    // where it came from (for messages and the summary)
  std::shared_ptr<const KeyLocations> keys;  // where the file wrote each key (for messages)
  std::string system;  // "A" (more systems follow)
  std::string name;
  std::string description;
  RunSettings run;
  sim::RigAConfig a;      // system A
  sim::RigEConfig e;      // system E
  sim::RigCConfig c;      // system C
  sim::RigBConfig b;      // system B
  bool b_compare = true;  // system B: also run without modulation
  std::vector<double> b_sweep_feed;  // system B: feeds for the with/without sweep
  std::string c_compare;  // system C: "", "linear" or "nonlinear" overlaid
  // system D
  struct Gauging {
    sim::GaugingProcess process;
    sensors::VibroContactGauge::Params transducer;
    double tolerance_m = 10e-6;            // ± about the target
    std::string threshold = "calibrated";  // "seed" (23 with A0, K) or "calibrated" (23 with the
                                           // full model's local line) or "given"
    double threshold_V = 0.0;              // when "given"
    std::size_t parts = 100000;            // linearised Monte Carlo
    std::size_t full_parts = 8;            // full-model Monte Carlo
  } d;
  std::vector<control::AdaptiveFeedController::Mode> compare_modes;  // system E: overlaid runs
  std::optional<Comparison> compare;
  std::vector<double> sweep_leak_estimate_factor;  // controller K_leak / true K_leak
};

Scenario parse_scenario(std::string_view text, const std::string& file_label,
                        const MaterialLibrary& materials);
Scenario load_scenario(const std::string& path, const MaterialLibrary& materials);

// A rig's (or a model's) rejection of a parsed scenario, as the InputError a user reads: a
// sim::ConfigError at the key it names, any other std::invalid_argument at `fallback_key` (a
// table whose settings it checks) or, without one, at the file.
[[noreturn]] void throw_at_key(const Scenario& sc, const std::invalid_argument& e,
                               const std::string& fallback_key = "");

std::string controller_kind_name(sim::ControllerKind k);
std::string regulator_kind_name(sim::RegulatorKind k);
std::string adaptive_mode_name(control::AdaptiveFeedController::Mode m);

}  // namespace lathectl::io
