// A generated system-E part for LinuxCNC: the scenario of the generator's seed
// (sim/e_part_generator.hpp), run in the rig `lathectl run` uses, and its passes written as the
// NC program that cuts them the same way (the rig's own sequence of moves, Rig::move()):
//
//   e_generated_program SEED OUT_DIR
//
// writes OUT_DIR/generated_SEED.toml and OUT_DIR/generated_SEED.ngc, and prints one JSON object:
// what was generated, the force parameter and its limit, whether the limit can be held at the
// minimum feed, and the rig's outcome (finished, cycle, per-revolution peak, alarms).
// tests/hal/linuxcnc_generated_test.py runs the program in LinuxCNC and holds both to the
// acceptance's invariants.
//
// The program, as a programmer writes the passes (G95, X the radius, Z0 at the bar's face, the
// part toward −Z): the spindle at V_p on the surface the pass starts on (one S per pass, set in
// air; the rig's programmed speed follows that surface along z, so on a stepped or tapered blank
// LinuxCNC's programmed speed is the pass's first section's), rapids above the part, G1 along the
// pass, and at a shoulder a radial plunge with its feed bound (M67 E2: set with the next move,
// no stop) put back to the scenario's with the pass that follows. G64 P0.01: the path within
// 10 µm of the program's corners, as the rig's (G64 alone let LinuxCNC's planner round the
// shoulder's corner over 2 mm of plunge, cutting a different chip than the rig's).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "lathectl/control/types.hpp"
#include "lathectl/io/scenario.hpp"
#include "sim/e_part_generator.hpp"
#include "support/library.hpp"
#include "systems/e_adaptive/metrics.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

namespace e = lathectl::systems::e_adaptive;

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4f", v);
  std::string s(b);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: e_generated_program SEED OUT_DIR\n");
    return 2;
  }
  const auto seed = static_cast<unsigned>(std::stoul(argv[1]));
  const std::string base = std::string(argv[2]) + "/generated_" + std::to_string(seed);
  const auto part = e::generated::generate(seed);
  std::ofstream(base + ".toml") << part.text;

  const auto sc =
      lathectl::systems::parse_scenario(part.text, base + ".toml", lathectl::test::library());
  const e::RigConfig& cfg = sc.get<e::Settings>().rig;
  e::Rig rig;
  rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  e::MetricsAccumulator acc(rig);
  rig.attach(&acc);

  const auto& cp = cfg.controller;
  lathectl::cutting::Stock stock;
  stock.configure(cfg.stock);
  const auto rpm_for = [&](std::size_t pass) {  // V_p on the surface the pass starts on
    const double z = std::max(cfg.stock.passes[pass].z_start_mm, 0.0);
    const double d = stock.surface_diameter_mm(pass, z);
    return std::round(std::clamp(cp.speed_programmed_m_per_min * 1000.0 / (std::numbers::pi * d),
                                 cfg.spindle.min_rpm, cfg.spindle.max_rpm));
  };
  const std::string F = " F" + num(cp.feed_programmed_mm_per_rev);
  std::ostringstream ngc;
  ngc << "(lathectl: generated part " << seed << " -- generated_" << seed
      << ".toml's passes as lathectl run's rig cuts them)\n"
      << "(" << part.what.substr(0, part.what.find(", blank")) << ")\n"
      << "G18 G21 G40 G80 G90 G95 G8 G64 P0.01\nT1 M6\n";
  using Kind = e::Rig::Move::Kind;
  auto last = rig.move();
  double blank_r = 0.0;
  for (const auto& b : cfg.stock.blank_diameter_mm) blank_r = std::max(blank_r, 0.5 * b.value);
  const double clear = std::ceil(blank_r + cfg.stock.eccentricity_mm + cfg.approach_mm + 1.0);
  ngc << "M3 S" << num(rpm_for(0)) << "\nG0 X" << num(clear) << " Z" << num(-last.z_mm) << "\n";
  bool plunge_bound = false;
  const auto emit = [&](const e::Rig::Move& m) {
    switch (m.kind) {
      case Kind::Descend:
        ngc << "G0 X" << num(m.x_mm) << "\n";
        break;
      case Kind::Plunge:
        ngc << "M67 E2 Q" << num(m.plunge_feed_max_mm_per_rev) << "\nG1 X" << num(m.x_mm) << F
            << "\n";
        plunge_bound = true;
        break;
      case Kind::Turn:
        if (plunge_bound) ngc << "M67 E2 Q0\n";
        plunge_bound = false;
        ngc << "G1 Z" << num(-m.z_mm) << F << "\n";
        break;
      case Kind::Retract:
        ngc << "G0 X" << num(m.x_mm) << "\n";
        break;
      case Kind::Return:
        ngc << "G0 Z" << num(-m.z_mm) << "\nS" << num(rpm_for(m.pass)) << "\n";
        break;
    }
  };
  emit(last);
  while (rig.step()) {
    const auto m = rig.move();
    if (m.kind != last.kind || m.pass != last.pass) emit(m);
    last = m;
  }
  ngc << "G0 X" << num(clear) << "\nG0 Z" << num(cfg.approach_mm) << "\nM5\nM2\n";
  std::ofstream(base + ".ngc") << ngc.str();

  const e::Metrics m = acc.result(rig);
  // The blank's sections: 1 for a bar of one diameter (its points all of one diameter).
  std::size_t sections = 1;
  for (std::size_t i = 1; i < cfg.stock.blank_diameter_mm.size(); ++i)
    if (cfg.stock.blank_diameter_mm[i].value != cfg.stock.blank_diameter_mm[i - 1].value) ++sections;
  const char* params[] = {"Pz", "Py", "power"};
  std::printf("{\"seed\": %u, \"what\": %s, \"parameter\": \"%s\", \"limit\": %.6g, "
              "\"reachable\": %s, \"type\": \"%s\", \"sections\": %zu, \"rig\": {\"finished\": %s, "
              "\"cycle_time_s\": %.4f, \"force_peak_rev_mean\": %.6g, \"alarms\": [",
              seed, json_string(part.what).c_str(),
              params[static_cast<int>(cfg.force_parameter)], cp.load_limit,
              e::generated::limit_reachable(cfg) ? "true" : "false",
              part.text.find("force_speed") != std::string::npos ? "force_speed" : "force_feed",
              sections,
              m.finished ? "true" : "false", m.cycle_time_s, m.force_peak_rev_mean);
  for (std::size_t i = 0; i < m.alarms.size(); ++i)
    std::printf("%s\"%s\"", i ? ", " : "",
                std::string(lathectl::control::reason_name(
                                static_cast<lathectl::control::Reason>(m.alarms[i].code)))
                    .c_str());
  std::printf("]}}\n");
  return 0;
}
