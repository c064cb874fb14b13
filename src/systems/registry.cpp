#include "systems/registry.hpp"

#include <array>
#include <sstream>

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
// run pointers (and the estimates and session reports) are null and all() and find(), whose
// callers run systems, are not defined: a null run cannot be reached.
#ifdef LATHECTL_SECTIONS_ONLY
#define LATHECTL_RUN(function) nullptr
#else
#include "systems/a_pulse_feed/entry.hpp"
#include "systems/a_pulse_feed/study.hpp"
#include "systems/b_chatter/entry.hpp"
#include "systems/b_chatter/study.hpp"
#include "systems/c_tracer/entry.hpp"
#include "systems/c_tracer/study.hpp"
#include "systems/d_gauging/entry.hpp"
#include "systems/d_gauging/study.hpp"
#include "systems/e_adaptive/entry.hpp"
#include "systems/e_adaptive/study.hpp"
#define LATHECTL_RUN(function) &function
#endif

namespace lathectl::systems {

namespace {
// The HAL components of each system on LinuxCNC (hal/<name>.cpp) and what each links besides
// the core. A's plant is rig A's plant and its metrics: it links A's whole library; D's gauge
// aims its size threshold as the study does (machine_threshold: the linearised parts).
constexpr HalComponent kSlideHal[] = {{"lathectl_slide", "lathectl_a_pulse_feed_settings"},
                                      {"lathectl_slide_plant", "lathectl_a_pulse_feed"}};
constexpr HalComponent kTwinHal[] = {{"lathectl_chatter", "lathectl_b_chatter_settings"},
                                     {"lathectl_modfeed", "lathectl_b_chatter_settings"}};
constexpr HalComponent kGaugeHal[] = {{"lathectl_gauge", "lathectl_d_gauging"},
                                      {"lathectl_gauge_plant", "lathectl_d_gauging_settings"}};
constexpr HalComponent kLatheHal[] = {{"lathectl_adaptive", "lathectl_e_adaptive_settings"},
                                      {"lathectl_plant", "lathectl_e_adaptive_settings"}};

// Each system: id, folder, title, docs page, section, run, estimate, and on LinuxCNC: runner,
// configuration, display, HAL components, session report.
const std::array<System, 5> kSystems{{
    {a_pulse_feed::kSection.system,
     "a_pulse_feed",
     "hydraulic feed slide with pulse regulation (seed 000)",
     "system-a-pulse-feed.md",
     &a_pulse_feed::kSection,
     LATHECTL_RUN(a_pulse_feed::run),
     LATHECTL_RUN(a_pulse_feed::estimate),
     {"linuxcnc-sim-slide", "lathectl-slide", "linuxcnc_slide_display.py", kSlideHal, {}}},
    {b_chatter::kSection.system,
     "b_chatter",
     "twin-turret chatter and modulated feed (seed 001)",
     "system-b-chatter.md",
     &b_chatter::kSection,
     LATHECTL_RUN(b_chatter::run),
     LATHECTL_RUN(b_chatter::estimate),
     {"linuxcnc-sim-twin",
      "lathectl-twin",
      "linuxcnc_twin_display.py",
      kTwinHal,
      {LATHECTL_RUN(b_chatter::is_session), LATHECTL_RUN(b_chatter::session_report)}}},
    {c_tracer::kSection.system,
     "c_tracer",
     "hydraulic copying slide (seed 002)",
     "system-c-tracer.md",
     &c_tracer::kSection,
     LATHECTL_RUN(c_tracer::run),
     LATHECTL_RUN(c_tracer::estimate),
     {}},
    {d_gauging::kSection.system,
     "d_gauging",
     "vibro-contact in-process gauging (seed 003)",
     "system-d-gauging.md",
     &d_gauging::kSection,
     LATHECTL_RUN(d_gauging::run),
     LATHECTL_RUN(d_gauging::estimate),
     {"linuxcnc-sim-gauge",
      "lathectl-gauge",
      "linuxcnc_gauge_display.py",
      kGaugeHal,
      {LATHECTL_RUN(d_gauging::is_session), LATHECTL_RUN(d_gauging::session_report)}}},
    // E's session report last: it takes any operation log.
    {e_adaptive::kSection.system,
     "e_adaptive",
     "adaptive control of force by feed and speed (seed 004)",
     "system-e-adaptive.md",
     &e_adaptive::kSection,
     LATHECTL_RUN(e_adaptive::run),
     LATHECTL_RUN(e_adaptive::estimate),
     {"linuxcnc-sim",
      "lathectl-lathe",
      "linuxcnc_sim_display.py",
      kLatheHal,
      {LATHECTL_RUN(e_adaptive::is_session), LATHECTL_RUN(e_adaptive::session_report)}}},
}};

std::vector<const io::Section*> sections() {
  std::vector<const io::Section*> out;
  for (const auto& s : kSystems) out.push_back(s.section);
  return out;
}
}  // namespace

#ifndef LATHECTL_SECTIONS_ONLY
std::span<const System> all() {
  return kSystems;
}

const System* find(std::string_view id) {
  for (const auto& s : kSystems)
    if (s.id == id) return &s;
  return nullptr;
}

std::string table_tsv() {
  const auto field = [](std::string_view v) {
    return v.empty() ? std::string("-") : std::string(v);
  };
  std::ostringstream o;
  o << "# id\tfolder\tdocs\trunner\tconfig\tdisplay\thal_components (name=links)\n";
  for (const auto& s : kSystems) {
    const auto& l = s.linuxcnc;
    std::string components;
    for (const auto& c : l.hal_components)
      components += (components.empty() ? "" : ",") + field(c.name) + "=" + field(c.links);
    o << s.id << '\t' << s.folder << '\t' << field(s.docs) << '\t' << field(l.runner) << '\t'
      << field(l.config) << '\t' << field(l.display) << '\t' << field(components) << '\n';
  }
  return o.str();
}
#endif

io::Scenario parse_scenario(std::string_view text, const std::string& label,
                            const io::MaterialLibrary& lib) {
  return io::parse_scenario(text, label, lib, sections());
}

io::Scenario load_scenario(const std::string& path, const io::MaterialLibrary& lib) {
  io::Scenario sc = parse_scenario(io::read_scenario_text(path), path, lib);
  io::print_warnings(sc);
  return sc;
}

}  // namespace lathectl::systems
