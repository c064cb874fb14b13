#pragma once
// The systems lathectl knows: the only central list. A new system is a folder
// (src/systems/<x>/: settings and their section reader, rig, metrics, study, claims, report
// layout, CMakeLists.txt) plus one line here, in registry.cpp, and in src/systems/CMakeLists.txt.

#include <span>
#include <string_view>

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems {

struct System {
  std::string_view id;      // the scenario's `system = "E"`
  std::string_view folder;  // src/systems/<folder>/, docs/<page>
  std::string_view title;   // "adaptive control (seed 004)"
  const io::Section* section;
  io::RunOutput (*run)(const io::Scenario& sc);
};

std::span<const System> all();
// nullptr when unknown.
const System* find(std::string_view id);

}  // namespace lathectl::systems
