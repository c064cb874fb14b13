// Scenario files (include/lathectl/io/scenario.hpp): every example parses; every kind of user
// mistake is an InputError that names the file, the line and the full key (DESIGN.md, "Scenario
// files and outputs").

#include "lathectl/io/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl::io {
namespace {

using lathectl::test::library;

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string& finishing_text() {
  static const std::string t = read(LATHECTL_SOURCE_DIR "/examples/scenarios/a_finishing_aim.toml");
  return t;
}

// Replaces the one occurrence of `from` (it must occur exactly once).
std::string edit(const std::string& from, const std::string& to) {
  return test::edited_once(finishing_text(), from, to);
}

using test::line_of;

// Parses `text` as "mem.toml" and returns the InputError message ("" if it did not throw).
std::string error_of(const std::string& text) {
  try {
    (void)systems::parse_scenario(text, "mem.toml", library());
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "parse_scenario did not throw";
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(Scenario, EveryExampleParses) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(LATHECTL_SOURCE_DIR "/examples/scenarios"))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  ASSERT_GE(files.size(), 10u);
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    Scenario sc;
    ASSERT_NO_THROW(sc = systems::load_scenario(f.string(), library()));
    EXPECT_TRUE(sc.system == "A" || sc.system == "B" || sc.system == "C" || sc.system == "D" ||
                sc.system == "E")
        << sc.system;
    EXPECT_EQ(sc.name, f.stem().string());  // each example is named after its file
    EXPECT_EQ(sc.file, f.string());
    EXPECT_GT(sc.run.duration_s, 0.0);
  }
}

TEST(Scenario, ShopUnitsConvertedToSi) {
  const Scenario sc = systems::parse_scenario(finishing_text(), "mem.toml", library());
  EXPECT_EQ(sc.file, "mem.toml");
  EXPECT_EQ(sc.name, "a_finishing_aim");
  EXPECT_DOUBLE_EQ(sc.run.duration_s, 12.0);
  EXPECT_EQ(sc.run.seed, 11u);
  const auto& st = sc.get<systems::a_pulse_feed::Settings>();
  const auto& a = st.rig;
  EXPECT_DOUBLE_EQ(a.spindle_rpm, 400.0);
  EXPECT_DOUBLE_EQ(a.diameter_m, 0.06);
  EXPECT_EQ(a.cutting.material.name, "steel_45");
  EXPECT_DOUBLE_EQ(a.part.depth_mm, 0.5);
  ASSERT_EQ(a.part.depth_steps.size(), 1u);
  EXPECT_DOUBLE_EQ(a.part.depth_steps[0].at_mm, 4.0);
  EXPECT_DOUBLE_EQ(a.part.depth_steps[0].value, 1.0);
  EXPECT_DOUBLE_EQ(a.regulator.orifice.spool_diameter_m, 5e-3);   // 5.0 mm
  EXPECT_DOUBLE_EQ(a.regulator.orifice.pressure_drop_Pa, 0.2e6);  // 0.2 MPa
  EXPECT_DOUBLE_EQ(a.pulse_width_s, 5e-3);                        // 5.0 ms
  EXPECT_DOUBLE_EQ(a.regulator.opening_time_s, 0.5e-3);
  EXPECT_DOUBLE_EQ(a.slide.piston_area_m2, 8e-4);    // 8 cm²
  EXPECT_DOUBLE_EQ(a.slide.dead_volume_m3, 60e-6);   // 60 cm³
  EXPECT_DOUBLE_EQ(a.slide.bulk_modulus_Pa, 1.4e9);  // 1400 MPa
  // 50 cm³/min/MPa = 50e−6 m³ / 60 s / 1e6 Pa = 8.3333e−13 m³/(s·Pa).
  EXPECT_NEAR(a.slide.leak_m3_per_s_Pa, 50e-6 / 60.0 / 1e6, 1e-25);
  // 0.5 cm³/MPa = 5e−13 m³/Pa; 0.06 MPa·s/cm³ = 6e10 Pa·s/m³.
  EXPECT_NEAR(a.slide.damper_capacitance_m3_per_Pa, 5e-13, 1e-25);
  EXPECT_NEAR(a.slide.damper_resistance_Pa_s_per_m3, 6e10, 1e-3);
  EXPECT_NEAR(a.sensor.holder_stiffness_N_per_m, 20e6, 1e-6);  // 20 N/µm
  EXPECT_NEAR(a.sensor.gain_V_per_m, 0.1e6, 1e-6);             // 0.1 V/µm
  EXPECT_EQ(a.controller_kind, systems::a_pulse_feed::ControllerKind::Aim);
  EXPECT_NEAR(a.controller.feed_m_per_s, 1e-3, 1e-15);  // 60 mm/min
  EXPECT_NEAR(a.controller.force_filter_s, 0.02, 1e-15);
  EXPECT_NEAR(a.feed_window_s, 0.5, 1e-15);
  ASSERT_TRUE(st.compare.has_value());
  EXPECT_EQ(st.compare->controller, systems::a_pulse_feed::ControllerKind::None);
  EXPECT_EQ(st.sweep_leak_estimate_factor, (std::vector<double>{0.5, 0.75, 1.0, 1.25, 1.5}));
}

TEST(Scenario, UnknownKeyNamesFileLineAndKey) {
  const std::string t = edit("[slide]\n", "[slide]\nbogus = 1\n");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "bogus")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "slide.bogus")) << msg;
  EXPECT_TRUE(contains(msg, "unknown key")) << msg;
}

TEST(Scenario, UnknownKeyInArrayOfTables) {
  const std::string t =
      edit("{ at_mm = 4.0, depth_mm = 1.0 }", "{ at_mm = 4.0, depth_mm = 1.0, colour = \"red\" }");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "colour")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "part.depth_steps[0].colour")) << msg;
  EXPECT_TRUE(contains(msg, "unknown key")) << msg;
}

TEST(Scenario, MissingRequiredKey) {
  const std::string t = edit("piston_area_cm2 = 8.0\n", "");
  const std::string msg = error_of(t);
  // The key is absent, so the message points at its table, [slide].
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "[slide]")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "slide.piston_area_cm2")) << msg;
  EXPECT_TRUE(contains(msg, "missing")) << msg;
}

TEST(Scenario, MissingRequiredTable) {
  std::string t = finishing_text();
  const auto a = t.find("[sensor]");
  const auto b = t.find("[controller]");
  t.erase(a, b - a);
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml")) << msg;
  EXPECT_TRUE(contains(msg, "'sensor'")) << msg;
  EXPECT_TRUE(contains(msg, "missing")) << msg;
}

TEST(Scenario, WrongType) {
  const std::string t = edit("mass_kg = 60.0", "mass_kg = \"heavy\"");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "mass_kg")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "slide.mass_kg")) << msg;
  EXPECT_TRUE(contains(msg, "expected a number")) << msg;
  EXPECT_TRUE(contains(msg, "a string")) << msg;
}

TEST(Scenario, OutOfRange) {
  const std::string t = edit("mass_kg = 60.0", "mass_kg = -3");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "mass_kg")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "slide.mass_kg")) << msg;
  EXPECT_TRUE(contains(msg, "-3")) << msg;  // says what it got
  EXPECT_TRUE(contains(msg, "expected a number")) << msg;
}

TEST(Scenario, OutOfRangeUpperBound) {
  // discharge_coefficient must lie in (0, 1].
  const std::string t = edit("discharge_coefficient = 0.65", "discharge_coefficient = 1.3");
  const std::string msg = error_of(t);
  EXPECT_TRUE(
      contains(msg, "mem.toml:" + std::to_string(line_of(t, "discharge_coefficient")) + ":"))
      << msg;
  EXPECT_TRUE(contains(msg, "regulator.discharge_coefficient")) << msg;
  EXPECT_TRUE(contains(msg, "(0, 1]")) << msg;
}

TEST(Scenario, UnknownMaterial) {
  const std::string t = edit("name = \"steel_45\"", "name = \"unobtainium\"");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "unobtainium")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "material.name")) << msg;
  EXPECT_TRUE(contains(msg, "unknown material")) << msg;
  EXPECT_TRUE(contains(msg, "steel_45")) << msg;  // lists what is known
}

TEST(Scenario, TomlSyntaxError) {
  const std::string t = edit("mass_kg = 60.0", "mass_kg = = 60.0");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "TOML syntax error")) << msg;
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "mass_kg")) + ":")) << msg;
}

TEST(Scenario, DuplicateKeyIsASyntaxError) {
  const std::string t = edit("mass_kg = 60.0", "mass_kg = 60.0\nmass_kg = 70.0");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "TOML syntax error")) << msg;
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "mass_kg = 70")) + ":")) << msg;
}

TEST(Scenario, BadEnumListsTheChoices) {
  const std::string t = edit("type = \"aim\"", "type = \"magic\"");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "magic")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "controller.type")) << msg;
  EXPECT_TRUE(contains(msg, "\"none\", \"aim\", \"fim\"")) << msg;
  EXPECT_TRUE(contains(msg, "magic")) << msg;
}

TEST(Scenario, DepthStepsMustAscend) {
  const std::string t =
      edit("depth_steps = [ { at_mm = 4.0, depth_mm = 1.0 } ]",
           "depth_steps = [ { at_mm = 4.0, depth_mm = 1.0 }, { at_mm = 2.0, depth_mm = 0.7 } ]");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "depth_steps")) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "part.depth_steps")) << msg;
}

TEST(Scenario, PulseLongerThanPeriodRejected) {
  // 20 Hz → T = 50 ms; a 60 ms pulse does not fit.
  const std::string t = edit("pulse_width_ms = 5.0", "pulse_width_ms = 60.0");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(t, "pulse_width_ms")) + ":"))
      << msg;
  EXPECT_TRUE(contains(msg, "regulator.pulse_width_ms")) << msg;
}

TEST(Scenario, StepTooCoarseForHydraulicsIsAnInputError) {
  // ω_h = F·sqrt(B/(V·m)) = 8e−4·sqrt(1.4e9/(60e−6·60)) = 499 rad/s: ω_h·dt = 2.5 at dt = 5 ms,
  // far beyond the rig's limit of 0.5. In range for the key, caught by the whole-scenario check.
  const std::string t =
      edit("step_s = 1e-4\nrecord_interval_s = 2e-3", "step_s = 5e-3\nrecord_interval_s = 1e-2");
  const std::string msg = error_of(t);
  EXPECT_TRUE(contains(msg, "mem.toml")) << msg;
  EXPECT_TRUE(contains(msg, "step_s")) << msg;
  EXPECT_TRUE(contains(msg, "too coarse")) << msg;
}

TEST(Scenario, MissingFileIsAnInputError) {
  EXPECT_THROW((void)systems::load_scenario(
                   LATHECTL_SOURCE_DIR "/examples/scenarios/no_such_file.toml", library()),
               InputError);
}

}  // namespace
}  // namespace lathectl::io

namespace lathectl::io {
namespace {

std::string twin_text() {
  std::ifstream in(LATHECTL_SOURCE_DIR "/examples/scenarios/b_twin_feed_division.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string b_error(const std::string& from, const std::string& to) {
  std::string t = twin_text();
  const auto at = t.find(from);
  if (at == std::string::npos) return "pattern not found: " + from;
  t.replace(at, from.size(), to);
  try {
    (void)systems::parse_scenario(t, "b.toml", library());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioB, ShopUnitsAndDefaultsFromTheMaterial) {
  const Scenario sc = systems::parse_scenario(twin_text(), "b.toml", library());
  EXPECT_EQ(sc.system, "B");
  const auto& settings = sc.get<systems::b_chatter::Settings>();
  const systems::b_chatter::RigConfig& b = settings.rig;
  EXPECT_DOUBLE_EQ(b.part.length_m, 0.6);
  EXPECT_DOUBLE_EQ(b.part.youngs_modulus_Pa, 210e9);
  EXPECT_EQ(b.setup, dynamics::TwinSetup::FeedDivision);
  EXPECT_EQ(b.cutting.form, cutting::ForceForm::Kienzle);
  EXPECT_DOUBLE_EQ(b.vibration.dead_zone_m, 5e-6);
  EXPECT_EQ(b.source, control::ModulationSource::Automatic);
  // F ∝ S^(1−m_p), F_p/F_c at each tool's chip s/2 = 0.07 mm (40Kh: 357·h^0.51 / 1940·h^0.74).
  EXPECT_DOUBLE_EQ(b.module.force_feed_exponent, 0.51);
  EXPECT_NEAR(b.module.radial_force_ratio,
              357.0 * std::pow(0.07, 0.51) / (1940.0 * std::pow(0.07, 0.74)), 1e-12);
  // m_d: the first mode's mass seen at the middle of the cut (285 mm of 600): ρAL/2 / sin².
  const double modal = 7850.0 * std::numbers::pi * 0.02 * 0.02 * 0.6 / 2.0;
  EXPECT_NEAR(b.module.part_mass_kg,
              modal / std::pow(std::sin(std::numbers::pi * 285.0 / 600.0), 2), 1e-9);
  ASSERT_EQ(settings.sweep_feed_mm_per_rev.size(), 8u);
}

TEST(ScenarioB, BadInputNamesTheKey) {
  EXPECT_TRUE(
      contains(b_error("setup = \"feed_division\"", "setup = \"triple\""), "key 'cut.setup'"));
  EXPECT_TRUE(contains(b_error("z_end_mm = 320", "z_end_mm = 700"), "key 'cut.z_end_mm'"));
  EXPECT_TRUE(contains(b_error("force_model = \"kienzle\"", "force_model = \"handbook\""),
                       "key 'material.force_model'"));
  EXPECT_TRUE(
      contains(b_error("turret = \"right\"", "turret = \"middle\""), "key 'modulation.turret'"));
  EXPECT_TRUE(contains(b_error("dead_zone_um = 5", "dead_zone_um = -5"),
                       "key 'vibration_sensor.dead_zone_um'"));
  EXPECT_TRUE(contains(b_error("modes = 2", "modes = 9"), "key 'part.modes'"));
  EXPECT_TRUE(
      contains(b_error("n_s = 5", "n_s = 5\nspeeed = 1"), "unknown key 'modulation.speeed'"));
  EXPECT_TRUE(contains(b_error("depth_mm = [0.5, 0.5]", "depth_mm = [0.5, 0.5, 0.5]"),
                       "key 'cut.depth_mm'"));
  EXPECT_TRUE(contains(b_error("duration_s = 60", "duration_s = 10"), "run"));
}

TEST(ScenarioB, ProgrammedParametersObeyTheSeedsQuanta) {
  std::string t = twin_text();
  const std::string from = "source = \"automatic\"";
  t.replace(t.find(from), from.size(),
            "source = \"programmed\"\nS_min_mm_per_min = 50\ndS_mm_per_min = 36.05\ndl_mm = 0.1");
  try {
    (void)systems::parse_scenario(t, "b.toml", library());
    ADD_FAILURE() << "ΔS = 36.05 accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "key 'modulation.dS_mm_per_min'")) << e.what();
  }
  t = twin_text();
  t.replace(t.find(from), from.size(),
            "source = \"programmed\"\nS_min_mm_per_min = 50\ndS_mm_per_min = 36\ndl_mm = 0.0005");
  try {
    (void)systems::parse_scenario(t, "b.toml", library());
    ADD_FAILURE() << "Δl = 0.5 µm accepted with a 1 µm resolution";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "key 'modulation.dl_mm'")) << e.what();
  }
}

// The keys a system's own tables read, each described once (settings.cpp): the reference lists
// them with a doc, including the ones only some choices read (the programmed modulation, the idle
// table, a given threshold).
std::vector<ParamRecord> own_rows(const Section& section, const std::vector<std::string>& tables) {
  std::vector<ParamRecord> out;
  for (const auto& r : describe_section(section, library()))
    for (const auto& t : tables)
      if (r.key.rfind(t + ".", 0) == 0 && r.kind != "table") out.push_back(r);
  return out;
}
bool described(const std::vector<ParamRecord>& rows, const std::string& key) {
  for (const auto& r : rows)
    if (r.key == key) return !r.doc.empty();
  return false;
}

TEST(ScenarioB, EveryKeyOfItsTablesIsDescribed) {
  const auto rows =
      own_rows(systems::b_chatter::kSection, {"part", "cut", "vibration_sensor", "power_sensor",
                                     "modulation", "process_damping", "study"});
  // part 6, cut 14 (cut.chip_law: issue 48), sensors 6 + 6, modulation 20, process damping 5,
  // study 2
  EXPECT_EQ(rows.size(), 59u);
  for (const auto& r : rows) EXPECT_FALSE(r.doc.empty()) << r.key;
  for (const char* k : {"cut.chip_law", "modulation.S_min_mm_per_min", "modulation.dl_mm",
                        "power_sensor.idle_table_rpm", "study.sweep_feed_mm_per_rev"})
    EXPECT_TRUE(described(rows, k)) << k;
  // The defaults shown are the settings' own, in the file's units.
  for (const auto& r : rows) {
    if (r.key == "vibration_sensor.dead_zone_um") {
      EXPECT_EQ(r.fallback, "5");
    }
    if (r.key == "modulation.engage_time_ms") {
      EXPECT_EQ(r.fallback, "50");
    }
  }
}

TEST(ScenarioD, EveryKeyOfItsTablesIsDescribed) {
  const auto rows =
      own_rows(systems::d_gauging::kSection, {"process", "transducer", "gauge", "monte_carlo"});
  EXPECT_EQ(rows.size(), 32u);  // process 8, transducer 18, gauge 4, monte_carlo 2
  for (const auto& r : rows) EXPECT_FALSE(r.doc.empty()) << r.key;
  EXPECT_TRUE(described(rows, "gauge.threshold_V"));
  for (const auto& r : rows) {
    if (r.key == "process.noise_sigma_um") {
      EXPECT_EQ(r.fallback, "0");
    }
  }
}

// System E's entry feed (issue "Results a user can trust", finding 3): a scenario key, default
// max(0.05 mm/rev, feed_min), checked against the feed limits with an error at the key. Before,
// the entry feed was fixed at 0.05 and any feed_min above it failed with "inconsistent scenario:
// adaptive controller: entry feed must be ≥ s_min" — no line, no key.
const std::string& seed004_text() {
  static const std::string t =
      read(LATHECTL_SOURCE_DIR "/examples/scenarios/e_stepped_seed004.toml");
  return t;
}

std::string edit_e(const std::string& from, const std::string& to) {
  std::string t = seed004_text();
  const auto pos = t.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) t.replace(pos, from.size(), to);
  return t;
}

TEST(ScenarioE, FeedMinAboveOldEntryFeedRunsWithEntryAtFeedMin) {
  const auto sc = systems::parse_scenario(
      edit_e("feed_min_mm_per_rev = 0.05", "feed_min_mm_per_rev = 0.1"), "mem.toml", library());
  EXPECT_DOUBLE_EQ(sc.get<systems::e_adaptive::Settings>().rig.controller.feed_min_mm_per_rev, 0.1);
  EXPECT_DOUBLE_EQ(sc.get<systems::e_adaptive::Settings>().rig.controller.entry_feed_mm_per_rev, 0.1);
  // The examples keep their 0.05.
  const auto ex = systems::parse_scenario(seed004_text(), "mem.toml", library());
  EXPECT_DOUBLE_EQ(ex.get<systems::e_adaptive::Settings>().rig.controller.entry_feed_mm_per_rev, 0.05);
}

TEST(ScenarioE, EntryFeedIsAKey) {
  const auto sc =
      systems::parse_scenario(edit_e("feed_min_mm_per_rev = 0.05",
                                     "feed_min_mm_per_rev = 0.05\nentry_feed_mm_per_rev = 0.12"),
                              "mem.toml", library());
  EXPECT_DOUBLE_EQ(sc.get<systems::e_adaptive::Settings>().rig.controller.entry_feed_mm_per_rev, 0.12);
}

TEST(ScenarioE, EntryFeedBelowFeedMinNamesLineAndKey) {
  const std::string text = edit_e("feed_min_mm_per_rev = 0.05",
                                  "feed_min_mm_per_rev = 0.1\nentry_feed_mm_per_rev = 0.08");
  const std::string msg = error_of(text);
  EXPECT_TRUE(contains(msg, "mem.toml:" + std::to_string(line_of(text, "entry_feed_mm_per_rev")) + ":"))
      << msg;
  EXPECT_TRUE(contains(msg, "controller.entry_feed_mm_per_rev")) << msg;
  EXPECT_TRUE(contains(msg, "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev] = [0.1, 0.8]"))
      << msg;
}

}  // namespace
}  // namespace lathectl::io
