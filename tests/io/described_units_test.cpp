// The reference and the run reports show each key's unit and default as its one description
// gives them, so they cannot drift: every key of every system is rendered from
// its description (describe_section) and compared with
//   - docs/scenario-reference.md, the committed output of `lathectl reference` (the test
//     docs_generated keeps the two equal), and
//   - the settings table of the report (io::settings_table) of every example scenario;
// and a default that follows a required key (the describe run answers required keys with
// made-up in-range values: "5" for feed_mm_per_rev) must be described as derived, never shown
// as the made-up number.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/registry.hpp"

namespace lathectl::io {
namespace {

using lathectl::test::library;

// The cells of a Markdown table row ("| a | b \| c |" → {"a", "b | c"}).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cur += '|';
      ++i;
    } else if (line[i] == '|') {
      const auto a = cur.find_first_not_of(' '), b = cur.find_last_not_of(' ');
      out.push_back(a == std::string::npos ? "" : cur.substr(a, b - a + 1));
      cur.clear();
    } else {
      cur += line[i];
    }
  }
  return out;
}

struct Shown {
  std::string unit, range, fallback;
};
// docs/scenario-reference.md: section ("common" or a system's id) → full key → what it shows.
std::map<std::string, std::map<std::string, Shown>> reference_rows() {
  std::ifstream in(LATHECTL_SOURCE_DIR "/docs/scenario-reference.md");
  EXPECT_TRUE(in) << "docs/scenario-reference.md";
  std::map<std::string, std::map<std::string, Shown>> out;
  std::string section, table;
  for (std::string line; std::getline(in, line);) {
    const std::string marker = "<!-- BEGIN generated: lathectl reference scenario ";
    if (line.rfind(marker, 0) == 0)
      section = line.substr(marker.size(), line.find(' ', marker.size()) - marker.size());
    if (line.rfind("### ", 0) == 0) {
      const auto a = line.find('`'), b = line.find('`', a + 1);
      table = a == std::string::npos ? "" : line.substr(a + 1, b - a - 1);  // [x] or [[x]]
      if (table.rfind("[[", 0) == 0)
        table = table.substr(2, table.size() - 4) + "[]";
      else if (!table.empty())
        table = table.substr(1, table.size() - 2);
    }
    if (line.rfind("<!-- END generated", 0) == 0) section.clear();
    if (section.empty() || line.rfind("| `", 0) != 0) continue;
    const auto c = cells(line);
    if (c.size() < 6) continue;
    const std::string key = c[0].substr(1, c[0].size() - 2);
    out[section][table.empty() ? key : table + "." + key] = {c[2], c[3], c[4]};
  }
  return out;
}

bool is_table(const ParamRecord& r) {
  return r.kind == "table" || r.kind == "array of tables";
}

bool is_number(const std::string& s) {
  char* end = nullptr;
  (void)std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0';
}

TEST(DescribedUnits, ReferenceShowsEachKeysDescribedUnitAndDefault) {
  const auto shown = reference_rows();
  ASSERT_TRUE(shown.count("common"));
  int compared = 0;
  for (const auto& s : systems::all()) {
    const ParamLog log = describe_section(*s.section, library());
    ASSERT_TRUE(shown.count(std::string(s.id))) << "no section for system " << s.id;
    const auto& mine = shown.at(std::string(s.id));
    for (const auto& r : log) {
      if (is_table(r)) continue;
      const auto& common = shown.at("common");
      const Shown* row = mine.count(r.key)     ? &mine.at(r.key)
                         : common.count(r.key) ? &common.at(r.key)
                                               : nullptr;
      ASSERT_TRUE(row) << s.id << ": " << r.key << " not in the reference";
      EXPECT_EQ(row->unit, r.unit) << s.id << ": unit of " << r.key;
      EXPECT_EQ(row->fallback, r.required ? "—" : r.fallback) << s.id << ": default of " << r.key;
      if (!r.plausible.empty()) {
        EXPECT_NE(row->range.find("usually " + r.plausible), std::string::npos)
            << s.id << ": plausible range of " << r.key;
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 200);
}

TEST(DescribedUnits, SettingsTablesShowEachKeysDescribedUnitAndDefault) {
  namespace fs = std::filesystem;
  int files = 0;
  for (const auto& f : fs::directory_iterator(LATHECTL_SOURCE_DIR "/examples/scenarios")) {
    if (f.path().extension() != ".toml") continue;
    const Scenario sc = systems::load_scenario(f.path().string(), library());
    EXPECT_TRUE(sc.warnings.empty()) << f.path() << ": " << sc.warnings.front();
    const systems::System* sys = systems::find(sc.system);
    ASSERT_TRUE(sys);
    std::map<std::string, ParamRecord> described;
    for (auto& r : describe_section(*sys->section, library())) {
      auto k = r.key;
      described[k] = r;
    }
    const Table t = settings_table(sc);
    for (const auto& row : t.rows) {
      // Array-of-tables rows ("stock.passes[2].diameter_mm") are described once ("passes[]").
      std::string k = row[0];
      for (std::size_t a; (a = k.find('[')) != std::string::npos && k[a + 1] != ']';)
        k.replace(a, k.find(']', a) - a, "[");
      const auto it = described.find(k);
      // A key only another branch's description reads; a table's line of meaning.
      if (it == described.end() || is_table(it->second)) continue;
      // A reading's unit is the sensor's the file chose ("N" of "N (Pz, Py) or W (power)").
      if (row[2] != it->second.unit) {
        EXPECT_TRUE(!row[2].empty() && it->second.unit.find(row[2] + " (") != std::string::npos)
            << f.path().filename() << ": unit of " << row[0] << ": " << row[2] << " vs "
            << it->second.unit;
      }
      if (it->second.required) {
        // Required, or optional with a derived default in another branch (feed_mm_per_rev with
        // worst_case_feed: feed_min_mm_per_rev).
        const auto& d = it->second.fallback;
        EXPECT_TRUE(row[3] == "required" || (!d.empty() && row[3].rfind(d + " = ", 0) == 0))
            << f.path().filename() << ": " << row[0] << ": " << row[3];
      } else if (is_number(it->second.fallback) || it->second.fallback == "true" ||
                 it->second.fallback == "false") {
        EXPECT_EQ(row[3], it->second.fallback) << f.path().filename() << ": default of " << row[0];
      } else if (it->second.fallback.size() > 0 && it->second.fallback[0] != '"' &&
                 it->second.fallback[0] != '[' && it->second.fallback != "derived" &&
                 it->second.fallback != "absent" && it->second.fallback[0] != '-') {
        // A derived default: the formula, then the value this file gives it.
        EXPECT_EQ(row[3].rfind(it->second.fallback + " = ", 0), 0u)
            << f.path().filename() << ": default of " << row[0] << ": " << row[3];
      }
    }
    ++files;
  }
  EXPECT_GT(files, 20);
}

// A default that moves when the required keys take other values is derived from them: its
// description must say from what (Param::derived), or the reference shows a made-up number.
TEST(DescribedUnits, DefaultsThatFollowRequiredKeysAreDescribedAsDerived) {
  for (const auto& s : systems::all()) {
    const ParamLog a = describe_section(*s.section, library(), 0);
    const ParamLog b = describe_section(*s.section, library(), 1);
    std::map<std::string, std::string> other;
    for (const auto& r : b) other[r.key] = r.fallback;
    for (const auto& r : a) {
      if (r.required || is_table(r) || !other.count(r.key)) continue;
      EXPECT_EQ(r.fallback, other[r.key])
          << "system " << s.id << ": the default of " << r.key
          << " follows a required key; describe it (Param::derived)";
    }
  }
}

// The units the house names carry (a minimum is not minutes).
TEST(DescribedUnits, NoKeyShowsMinutesForAMinimum) {
  for (const auto& s : systems::all())
    for (const auto& r : describe_section(*s.section, library())) {
      const std::string name = r.key.substr(r.key.rfind('.') + 1);
      if (name.find("_min_") != std::string::npos || name.ends_with("_min")) {
        EXPECT_NE(r.unit.rfind("min·", 0), 0u) << r.key << ": " << r.unit;
      }
    }
}

}  // namespace
}  // namespace lathectl::io
