#pragma once
// The systems lathectl knows: the only central list. A new system is a folder
// (src/systems/<x>/: settings.{hpp,cpp} with the section reader and kSection, validate.cpp,
// rig.{hpp,cpp}, metrics.{hpp,cpp}, study.{hpp,cpp}, CMakeLists.txt; docs/code-layout.md) plus
// one entry in registry.cpp. lathectl_systems defines what is declared here; lathectl_sections
// (registry.cpp without the runs, for what only reads scenarios) defines io::parse_scenario and
// io::load_scenario alone.

#include <span>
#include <string_view>

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems {

struct System {
  std::string_view id;      // the scenario's `system = "E"` (its section's letter)
  std::string_view folder;  // src/systems/<folder>/, docs/<page>
  std::string_view title;   // "adaptive control (seed 004)"
  const io::Section* section;
  io::RunOutput (*run)(const io::Scenario& sc);
};

std::span<const System> all();
// nullptr when unknown.
const System* find(std::string_view id);

}  // namespace lathectl::systems
