#pragma once
// The systems lathectl knows: the only central list, and everything per system that is not in
// its folder's code. A new system is a folder (src/systems/<x>/: settings.{hpp,cpp} with the
// section reader and kSection, validate.cpp, rig.{hpp,cpp}, metrics.{hpp,cpp}, study.{hpp,cpp},
// entry.hpp and estimate.cpp, CMakeLists.txt) plus one entry in registry.cpp ("Adding a system"
// in docs/code-layout.md). What the build and the scripts need of an entry (its HAL components,
// its LinuxCNC runner and configuration, its docs page) they read from hal/systems.tsv, which
// `lathectl systems --tsv` writes from these entries (the test systems_table checks it).
// lathectl_systems defines what is declared here; lathectl_sections (registry.cpp without the
// runs, for what only reads scenarios) defines parse_scenario and load_scenario alone.

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "lathectl/io/estimate.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems {

// `lathectl report PATH` of what the system's LinuxCNC runner wrote (null: none).
struct SessionReport {
  bool (*is_session)(const std::filesystem::path& path) = nullptr;  // the registry asks in order
  int (*report)(const std::filesystem::path& path, const std::string& out) = nullptr;
};

// A HAL component: it links lathectl_core and `links` (a library lathectl_system() built for its
// system: its settings library, or more where it runs the rig's plant).
struct HalComponent {
  std::string_view name;   // hal/<name>.cpp, hal/man/<name>.9
  std::string_view links;  // "lathectl_e_adaptive_settings"
};

// The system on LinuxCNC (empty: it has none).
struct LinuxCnc {
  // scripts/<runner> (installed as lathectl-<runner>): runs a scenario of the system on
  // LinuxCNC's simulated machine; scripts/linuxcnc-sim hands a scenario to its system's.
  std::string_view runner;
  std::string_view config;   // hal/config/<config>.ini and .hal: the machine's configuration
  std::string_view display;  // scripts/<display>: the runner's headless display
  // hal/<name>.cpp, hal/man/<name>.9: its HAL components.
  std::span<const HalComponent> hal_components;
  SessionReport session;
};

struct System {
  std::string_view id;      // the scenario's `system = "E"` (its section's letter)
  std::string_view folder;  // src/systems/<folder>/
  std::string_view title;   // "adaptive control (seed 004)"
  std::string_view docs;    // docs/<docs>: the system's page
  const io::Section* section;
  io::RunOutput (*run)(const io::Scenario& sc);
  io::RunEstimate (*estimate)(const io::Scenario& sc);  // its study's cost (entry.hpp)
  LinuxCnc linuxcnc;
};

std::span<const System> all();
// nullptr when unknown.
const System* find(std::string_view id);
// The entries as hal/systems.tsv holds them: a header line, then one line per system, fields
// separated by tabs, lists by commas (a component as name=links), "-" for none.
std::string table_tsv();

// A scenario of any system: the general io::parse_scenario over every system's section.
io::Scenario parse_scenario(std::string_view text, const std::string& file_label,
                            const io::MaterialLibrary& materials);
// The same from a file, its warnings printed on stderr.
io::Scenario load_scenario(const std::string& path, const io::MaterialLibrary& materials);
// Runs the scenario's system's study (its entry's run) and finishes its output (io::finish_run).
// Throws InputError (bad scenario) or std::runtime_error (numerical failure: NaN, divergence).
io::RunOutput run_scenario(const io::Scenario& sc);

}  // namespace lathectl::systems
