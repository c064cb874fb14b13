#include "systems/registry.hpp"

#include <array>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/system_a.hpp"
#include "lathectl/io/system_b.hpp"
#include "lathectl/io/system_c.hpp"
#include "lathectl/io/system_d.hpp"
#include "../io/scenario_legacy.hpp"
#include "systems/e_adaptive/study.hpp"

namespace lathectl::systems {

namespace {
// Transitional (issue 12): systems whose section reader is still src/io/scenario_legacy.cpp.
constexpr io::Section kLegacyA{"A", &io::read_legacy};
constexpr io::Section kLegacyB{"B", &io::read_legacy};
constexpr io::Section kLegacyC{"C", &io::read_legacy};
constexpr io::Section kLegacyD{"D", &io::read_legacy};

const std::array<System, 5> kSystems{{
    {"A", "a_pulse_feed", "hydraulic feed slide with pulse regulation (seed 000)", &kLegacyA,
     &io::run_system_a},
    {"B", "b_chatter", "twin-turret chatter and modulated feed (seed 001)", &kLegacyB,
     &io::run_system_b},
    {"C", "c_tracer", "hydraulic copying slide (seed 002)", &kLegacyC, &io::run_system_c},
    {"D", "d_gauging", "vibro-contact in-process gauging (seed 003)", &kLegacyD,
     &io::run_system_d},
    {"E", "e_adaptive", "adaptive control of force by feed and speed (seed 004)", &e_adaptive::kSection,
     &e_adaptive::run},
}};

std::vector<const io::Section*> sections() {
  std::vector<const io::Section*> out;
  for (const auto& s : kSystems) out.push_back(s.section);
  return out;
}
}  // namespace

std::span<const System> all() { return kSystems; }

const System* find(std::string_view id) {
  for (const auto& s : kSystems)
    if (s.id == id) return &s;
  return nullptr;
}

}  // namespace lathectl::systems

namespace lathectl::io {

Scenario parse_scenario(std::string_view text, const std::string& label,
                        const MaterialLibrary& lib) {
  return parse_scenario(text, label, lib, systems::sections());
}

Scenario load_scenario(const std::string& path, const MaterialLibrary& lib) {
  return parse_scenario(read_scenario_text(path), path, lib);
}

}  // namespace lathectl::io
