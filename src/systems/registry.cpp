#include "systems/registry.hpp"

#include <array>

#include "lathectl/io/errors.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/c_tracer/settings.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/e_adaptive/settings.hpp"

// This one list is compiled twice (src/systems/CMakeLists.txt). Into lathectl_systems, for the
// program: each system's section and its run. Into lathectl_sections, with LATHECTL_SECTIONS_ONLY
// defined, for what only reads scenarios (the fuzz build's scenario_fuzz): the sections alone,
// so that no system's study, metrics or report layout is compiled or linked for it. There the
// run pointers are null and all() and find(), whose callers run systems, are not defined: a null
// run cannot be reached.
#ifdef LATHECTL_SECTIONS_ONLY
#define LATHECTL_RUN(system) nullptr
#else
#include "systems/a_pulse_feed/study.hpp"
#include "systems/b_chatter/study.hpp"
#include "systems/c_tracer/study.hpp"
#include "systems/d_gauging/study.hpp"
#include "systems/e_adaptive/study.hpp"
#define LATHECTL_RUN(system) &system::run
#endif

namespace lathectl::systems {

namespace {
const std::array<System, 5> kSystems{{
    {a_pulse_feed::kSection.system, "a_pulse_feed",
     "hydraulic feed slide with pulse regulation (seed 000)", &a_pulse_feed::kSection,
     LATHECTL_RUN(a_pulse_feed)},
    {b_chatter::kSection.system, "b_chatter", "twin-turret chatter and modulated feed (seed 001)",
     &b_chatter::kSection, LATHECTL_RUN(b_chatter)},
    {c_tracer::kSection.system, "c_tracer", "hydraulic copying slide (seed 002)",
     &c_tracer::kSection, LATHECTL_RUN(c_tracer)},
    {d_gauging::kSection.system, "d_gauging", "vibro-contact in-process gauging (seed 003)",
     &d_gauging::kSection, LATHECTL_RUN(d_gauging)},
    {e_adaptive::kSection.system, "e_adaptive",
     "adaptive control of force by feed and speed (seed 004)", &e_adaptive::kSection,
     LATHECTL_RUN(e_adaptive)},
}};

std::vector<const io::Section*> sections() {
  std::vector<const io::Section*> out;
  for (const auto& s : kSystems) out.push_back(s.section);
  return out;
}
}  // namespace

#ifndef LATHECTL_SECTIONS_ONLY
std::span<const System> all() { return kSystems; }

const System* find(std::string_view id) {
  for (const auto& s : kSystems)
    if (s.id == id) return &s;
  return nullptr;
}
#endif

}  // namespace lathectl::systems

namespace lathectl::io {

Scenario parse_scenario(std::string_view text, const std::string& label,
                        const MaterialLibrary& lib) {
  return parse_scenario(text, label, lib, systems::sections());
}

Scenario load_scenario(const std::string& path, const MaterialLibrary& lib) {
  Scenario sc = parse_scenario(read_scenario_text(path), path, lib);
  print_warnings(sc);
  return sc;
}

}  // namespace lathectl::io
