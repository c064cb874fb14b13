// Messages that name the user's mistake, not its symptom: an unknown table or
// key is reported at its own line with the known name nearest to it, in preference to the
// "missing" error it causes; a known quantity written in another unit is recognised and the
// converted value given; values inside the valid range but outside what a shop would mean are
// warnings naming the key. The reader (io/toml_reader) does this for every file it reads:
// scenarios and the lobes machine file alike.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "systems/registry.hpp"

namespace lathectl::io {
namespace {

using lathectl::test::library;

std::string read_example(const std::string& name) {
  std::ifstream in(std::string(LATHECTL_SOURCE_DIR "/examples/") + name, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The E example with `from` (occurring once) replaced by `to`.
std::string e_with(const std::string& from, const std::string& to) {
  return test::edited_once(read_example("scenarios/e_stepped_seed004.toml"), from, to);
}

using test::line_of;

// "mem.toml:L:C: " of a table header `needle`, or of the value of the key `needle` (the reader
// locates a key at its value, as toml++ records it).
std::string at(const std::string& text, const std::string& needle, const char* file = "mem.toml") {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  const auto bol = pos == 0 ? 0 : text.rfind('\n', pos - 1) + 1;  // npos + 1 = 0: first line
  auto col = pos - bol + 1;
  if (needle[0] != '[') col = text.find('=', pos) + 2 - bol + 1;
  return std::string(file) + ":" + std::to_string(line_of(text, needle)) + ":" +
         std::to_string(col) + ": ";
}

std::string error_of(const std::string& text) {
  try {
    (void)systems::parse_scenario(text, "mem.toml", library());
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "parse_scenario did not throw";
  return "";
}

TEST(Messages, MisspeltRequiredTableIsReportedAtItsOwnLine) {
  // Before: "mem.toml:1:1: key 'spindle': missing table".
  const auto t = e_with("[spindle]", "[spindel]");
  EXPECT_EQ(error_of(t), at(t, "[spindel]") + "unknown table 'spindel' — did you mean 'spindle'?");
}

TEST(Messages, MisspeltRequiredKeyIsReportedNotTheMissingOne) {
  // Before: "key 'controller.planned_depth_mm': missing; expected a number (0, 50]".
  const auto t = e_with("planned_depth_mm = 3.0", "planned_depht_mm = 3.0");
  EXPECT_EQ(error_of(t), at(t, "planned_depht_mm") +
                             "unknown key 'controller.planned_depht_mm' — did you mean "
                             "'controller.planned_depth_mm'?");
}

TEST(Messages, MisspeltOptionalKeyAndTableSuggestTheNearest) {
  auto t = e_with("approach_mm = 2.0", "aproach_mm = 2.0");
  EXPECT_EQ(error_of(t), at(t, "aproach_mm") +
                             "unknown key 'stock.aproach_mm' — did you mean 'stock.approach_mm'?");
  t = e_with("[cost]", "[cots]");
  EXPECT_EQ(error_of(t), at(t, "[cots]") + "unknown table 'cots' — did you mean 'cost'?");
  // Nothing near: the list of the table's keys, as before.
  t = e_with("approach_mm = 2.0", "approach_mm = 2.0\nbanana = 1");
  const auto e = error_of(t);
  EXPECT_EQ(e.rfind(at(t, "banana") + "unknown key 'stock.banana' (known here: ", 0), 0u) << e;
}

TEST(Messages, KnownQuantityInAnotherUnitGivesTheConvertedValue) {
  // Before: "key 'spindle.max_power_kW': missing; expected a number > 0".
  auto t = e_with("max_power_kW = 22.0", "max_power_W = 22000");
  EXPECT_EQ(error_of(t), at(t, "max_power_W") +
                             "unknown key 'spindle.max_power_W': max power is given in kW: "
                             "max_power_kW = 22.0 for 22000 W");
  // An optional key: found when the table is finished.
  t = e_with("rapid_mm_per_min = 6000.0", "rapid_mm_per_s = 100");
  EXPECT_EQ(error_of(t), at(t, "rapid_mm_per_s") +
                             "unknown key 'feed_axis.rapid_mm_per_s': rapid is given in "
                             "mm/min: rapid_mm_per_min = 6000.0 for 100 mm/s");
  t = e_with("time_constant_ms = 2.0", "time_constant_s = 0.002");
  EXPECT_NE(error_of(t).find("time_constant_ms = 2.0 for 0.002 s"), std::string::npos);
  // Another quantity under the same name: no conversion, the unit the key wants.
  t = e_with("planned_depth_mm = 3.0", "planned_depth_mm_per_rev = 3.0");
  EXPECT_NE(error_of(t).find("unknown key 'controller.planned_depth_mm_per_rev': planned depth "
                             "is given in mm: planned_depth_mm (mm/rev is not a unit of it)"),
            std::string::npos);
}

TEST(Messages, MisspeltChoiceSuggestsTheNearest) {
  const auto t = e_with("type = \"force_speed\"", "type = \"forcespeed\"");
  const auto e = error_of(t);
  EXPECT_NE(e.find("got \"forcespeed\" — did you mean \"force_speed\"?"), std::string::npos) << e;
}

TEST(Messages, TheLobesMachineFileReaderSaysTheSame) {
  // Before: "key 'mode[0].stiffness_N_per_m': missing; expected a number (0, 1e+13]".
  std::string t = read_example("machines/b_sdof.toml");
  t.replace(t.find("stiffness_N_per_m = 2.26e8"), 26, "stiffness_N_per_um = 226");
  try {
    (void)systems::b_chatter::parse_lobes_input(t, "m.toml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              at(t, "stiffness_N_per_um", "m.toml") +
                  "unknown key 'mode[0].stiffness_N_per_um': stiffness is given in N/m: "
                  "stiffness_N_per_m = 2.26e8 for 226 N/µm");
  }
}

TEST(Messages, UnitsAndNearestNames) {
  EXPECT_EQ(unit_of_key("feed_min_mm_per_rev"), "mm/rev");  // a minimum feed, not min·mm/rev
  EXPECT_EQ(unit_of_key("frequency_min_Hz"), "Hz");
  EXPECT_EQ(unit_of_key("S_min_mm_per_min"), "mm/min");
  EXPECT_EQ(unit_of_key("tool_change_min"), "min");  // minutes
  EXPECT_EQ(unit_of_key("leak_cm3_per_min_per_MPa"), "cm³/min/MPa");
  EXPECT_EQ(unit_of_key("feed_rate_limit_per_s"), "1/s");
  EXPECT_EQ(unit_of_key("inertia_kg_m2"), "kg·m²");
  EXPECT_EQ(unit_of_key("n_s"), "");
  const auto m = unit_mismatch("speed_rpm", "speed_Hz");
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->factor, 1.0 / 60.0, 1e-15);
  EXPECT_NEAR(unit_mismatch("pressure_bar", "pressure_MPa")->factor, 0.1, 1e-15);
  EXPECT_NEAR(unit_mismatch("wait_min", "wait_s")->factor, 60.0, 1e-12);
  EXPECT_NEAR(unit_mismatch("feed_mm_per_min", "feed_mm_per_s")->factor, 1.0 / 60.0, 1e-15);
  EXPECT_TRUE(std::isnan(unit_mismatch("feed_mm_per_min", "feed_mm_per_rev")->factor));
  EXPECT_FALSE(unit_mismatch("depth_mm", "feed_mm"));
  EXPECT_EQ(nearest_name("spindel", {"run", "spindle", "stock"}), "spindle");
  EXPECT_EQ(nearest_name("tol", {"run", "tool"}), "tool");
  EXPECT_EQ(nearest_name("Spindle", {"spindle"}), "spindle");  // case ignored
  EXPECT_EQ(nearest_name("banana", {"spindle", "stock"}), "");
}

// Values inside the valid range that a shop would never mean: read, and a warning naming the
// key (stderr and the report take them from Scenario::warnings).
std::vector<std::string> warnings_of(const std::string& text) {
  return systems::parse_scenario(text, "mem.toml", library()).warnings;
}

TEST(Messages, ImplausibleValuesAreWarnings) {
  EXPECT_TRUE(warnings_of(read_example("scenarios/e_stepped_seed004.toml")).empty());

  auto t = e_with("speed_m_per_min = 150.0", "speed_m_per_min = 1600.0");
  auto w = warnings_of(t);
  ASSERT_EQ(w.size(), 2u);
  const std::string where = at(t, "speed_m_per_min");
  EXPECT_EQ(w[0], where +
                      "key 'controller.speed_m_per_min': 1600 m/min is not a value a shop "
                      "would mean (usually [10, 600] m/min); check the number and its unit");
  EXPECT_EQ(w[1].rfind(where + "key 'controller.speed_m_per_min': at V_p = 1600 m/min", 0), 0u)
      << w[1];
  EXPECT_NE(w[1].find("the tool life on steel_45 would be "), std::string::npos) << w[1];

  // A pass entirely in air: the third pass to Ø80 after the second cut to Ø74.
  t = e_with("{ z_start_mm = 150.0, z_end_mm = 300.0, diameter_mm = 70.0 }",
             "{ z_start_mm = 150.0, z_end_mm = 300.0, diameter_mm = 80.0 }");
  w = warnings_of(t);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("key 'stock.passes[2].diameter_mm': the pass cuts nothing: 80 mm "
                      "is at or above the largest diameter in front of it on z = [150, 300] mm "
                      "(74 mm): it runs entirely in air"),
            std::string::npos)
      << w[0];
}

TEST(Messages, ImplausibleToleranceAndModeStiffness) {
  std::string t = read_example("scenarios/d_gauging.toml");
  const auto pos = t.find("tolerance_um = ");
  ASSERT_NE(pos, std::string::npos);
  t.replace(pos, t.find('\n', pos) - pos, "tolerance_um = 0.005");
  auto w = warnings_of(t);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("key 'process.tolerance_um': 0.005 µm is not a value a shop would "
                      "mean (usually [0.5, 5000] µm)"),
            std::string::npos)
      << w[0];
}

}  // namespace

// What a file or flag holds reaches the terminal escaped and bounded (issue 49: escape sequences
// and 10 MB header lines were echoed raw into the one error line): every control byte, C1
// control and non-UTF-8 byte as \xNN, UTF-8 kept, cut with "…".
TEST(Printable, EscapesControlsAndCutsLongText) {
  EXPECT_EQ(io::printable("a\x1b[31mb\x07\n"), "a\\x1b[31mb\\x07\\x0a");
  EXPECT_EQ(io::printable("\xc2\x9b" "2J \xff\xfe µ·→ \xed\xa0\x80"),
            "\\xc2\\x9b2J \\xff\\xfe µ·→ \\xed\\xa0\\x80");
  const std::string cut = io::printable(std::string(10'000'000, 'A'));
  EXPECT_EQ(cut.size(), 203u);  // 200 characters and "…" (3 bytes)
  EXPECT_EQ(cut.find_first_not_of('A'), 200u);
  EXPECT_EQ(cut.substr(200), "…");
  EXPECT_EQ(io::printable("µµµµ", 3), "µµµ…");
  EXPECT_EQ(io::printable("abc", 3), "abc");
  EXPECT_EQ(io::error_line(std::string(5000, 'x')).size(), io::kMaxErrorLineChars + 3);
}

}  // namespace lathectl::io
