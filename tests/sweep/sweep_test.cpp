// lathectl sweep's parts (src/sweep/): the spec reader's order and errors, the cases' order and
// draws, a value applied by toml++ (bit for bit), the values checked by the scenario's reader,
// the results store's once-only record, the metrics' names. End to end: tests/cli/sweep_test.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <toml++/toml.h>
#include <unistd.h>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "sweep/cases.hpp"
#include "sweep/engine.hpp"
#include "sweep/spec.hpp"
#include "sweep/store.hpp"

namespace lathectl::sweep {
namespace {

namespace fs = std::filesystem;
const std::string kScenario =
    std::string(LATHECTL_SOURCE_DIR) + "/examples/scenarios/a_finishing_aim.toml";

std::string error_of(const std::string& spec) {
  try {
    parse_spec(spec, "s.toml");
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SweepSpec, KeysInTheSpecsOrderNotTomlsSortedOne) {
  const auto s = parse_spec(
      "scenario = \"x.toml\"\n[grid]\n\"z.b\" = [1, 2]\n\"a.c\" = [\"u\"]\n"
      "[random]\nsamples = 3\nseed = 9\n\"y.d\" = { normal = [1, 0.5] }\n\"b.e\" = { choice = "
      "[true, false] }\n[output]\nmetrics = [\"m.n\"]\n",
      "dir/s.toml");
  ASSERT_EQ(s.grid.size(), 2u);
  EXPECT_EQ(s.varied_keys(), (std::vector<std::string>{"z.b", "a.c", "y.d", "b.e"}));
  EXPECT_EQ(s.samples, 3u);
  EXPECT_EQ(s.seed, 9u);
  EXPECT_EQ(s.metrics, std::vector<std::string>{"m.n"});
  EXPECT_EQ(s.scenario, fs::absolute("dir/x.toml").lexically_normal());
  EXPECT_EQ(s.place_of("y.d").line, 8);
}

TEST(SweepSpec, ErrorsNameTheLineAndKey) {
  EXPECT_EQ(error_of("scenario = \"x\"\n[grid]\n\"a.b\" = 3\n").rfind("s.toml:3:", 0), 0u);
  EXPECT_NE(error_of("scenario = \"x\"\n[grid]\n\"ab\" = [3]\n").find("s.toml:3:"), std::string::npos);
  EXPECT_EQ(error_of("scenario = \"x\"\n[random]\nsamples = 2\n\"a.b\" = { uniform = [2, 1] }\n")
                .rfind("s.toml:4:", 0), 0u);
  EXPECT_EQ(error_of("scenario = \"x\"\n[random]\nsamples = 2\n\"a.b\" = { normal = [2, 0] }\n")
                .rfind("s.toml:4:", 0), 0u);
  EXPECT_NE(error_of("scenario = \"x\"\n[random]\n\"a.b\" = { uniform = [1, 2] }\n")
                .find("random.samples"), std::string::npos);
  EXPECT_NE(error_of("scenario = \"x\"\n[grid]\n\"a.b\" = [1]\n[random]\nsamples = 1\n\"a.b\" = "
                     "{ uniform = [1, 2] }\n").find("varied in [grid] and [random]"),
            std::string::npos);
  EXPECT_NE(error_of("scenario = \"x\"\nmetrics = 1\n").find("s.toml:2:"), std::string::npos);
  EXPECT_NE(error_of("[grid]\n\"a.b\" = [1]\n").find("key 'scenario'"), std::string::npos);
  EXPECT_NE(error_of("scenario = \"x\"\n").find("nothing to vary"), std::string::npos);
}

TEST(SweepSpec, ReportNamesTwoGridAxesAndIsRefusedAtItsLine) {
  const std::string head = "scenario = \"x\"\n[grid]\n\"c.f\" = [0.1, 0.2]\n\"c.n\" = [1, 2]\n"
                           "\"c.d\" = [0.5]\n[report]\nlobes = \"m.toml\"\n";  // lines 1-7
  const auto s = parse_spec(head + "speed = \"c.n\"\ndepth = \"c.f\"\ndepth_reference = 0.1\n"
                                   "depth_exponent = 0.49\nchatter = \"g.x\"\nchatter_above = 2\n",
                            "dir/s.toml");
  ASSERT_TRUE(s.lobes);
  EXPECT_EQ(s.lobes->machine, fs::absolute("dir/m.toml").lexically_normal());
  EXPECT_EQ(s.lobes->speed, "c.n");
  EXPECT_EQ(s.lobes->depth_exponent, 0.49);
  EXPECT_EQ(s.lobes->chatter_above, 2.0);
  const auto at = [&](const std::string& tail, const std::string& where) {
    const std::string e = error_of(head + tail);
    EXPECT_EQ(e.rfind("s.toml:" + where, 0), 0u) << e;
  };
  at("speed = \"c.n\"\ndepth = \"c.d\"\n", "9:9: key 'report.depth'");  // the third grid key
  at("speed = \"c.n\"\ndepth = \"c.n\"\n", "9:9: key 'report.depth': the same");
  at("speed = \"c.x\"\ndepth = \"c.f\"\n", "8:9: key 'report.speed'");
  at("speed = \"c.n\"\n", "6:1: key 'report.depth': required");
  at("speed = \"c.n\"\ndepth = \"c.f\"\ndepth_exponent = 0.5\n", "6:1: key 'report.depth_reference'");
  at("speed = \"c.n\"\ndepth = \"c.f\"\ndepth_exponent = 1\n", "10:18: key 'report.depth_exponent'");
  at("speed = \"c.n\"\ndepth = \"c.f\"\ncolour = 1\n", "10:10: key 'report.colour': unknown");
}

TEST(SweepCases, GridLastKeyFastestCrossedWithTheSamples) {
  const auto s = parse_spec(
      "scenario = \"x\"\n[grid]\n\"a.x\" = [1, 2]\n\"a.y\" = [10, 20, 30]\n[random]\n"
      "samples = 2\nseed = 5\n\"a.z\" = { uniform = [0, 1] }\n",
      "s.toml");
  const auto v = draw_values(s);
  ASSERT_EQ(v.size(), 12u);
  for (std::size_t c = 0; c < v.size(); ++c) {
    const std::size_t p = c / 2;
    EXPECT_EQ(std::get<std::int64_t>(v[c][0]), p / 3 + 1);
    EXPECT_EQ(std::get<std::int64_t>(v[c][1]), 10 * static_cast<std::int64_t>(p % 3 + 1));
    EXPECT_EQ(std::get<double>(v[c][2]), std::get<double>(v[c % 2][2]));  // the same samples
    EXPECT_GE(std::get<double>(v[c][2]), 0.0);
    EXPECT_LT(std::get<double>(v[c][2]), 1.0);
  }
  EXPECT_NE(std::get<double>(v[0][2]), std::get<double>(v[1][2]));
  EXPECT_EQ(draw_values(s), v);  // drawn again: the same
  auto other = s;
  other.seed = 6;
  EXPECT_NE(std::get<double>(draw_values(other)[0][2]), std::get<double>(v[0][2]));
}

TEST(SweepCases, ApplySetsKeysElementsAndDropsStudiesBitForBit) {
  const std::string base =
      "[run]\nduration_s = 1.0\n[part]\nsteps = [ { at_mm = 4.0, depth_mm = 1.0 } ]\n"
      "d = [0.5, 0.7]\n[compare]\ncontroller = \"none\"\n[sweep]\nk = [1.0]\n[study]\nx = 1\n";
  const double odd = 0.1 + 0.2;  // 0.30000000000000004: needs 17 digits
  const auto text = apply(base, "t", {"run.duration_s", "part.d[1]", "part.steps[0].depth_mm",
                                      "cut.rpm", "run.seed"},
                          {Value{odd}, Value{std::int64_t{3}}, Value{2.5}, Value{std::int64_t{450}},
                           Value{std::int64_t{7}}});
  const auto t = toml::parse(text);
  EXPECT_EQ(t["run"]["duration_s"].value<double>(), odd);
  EXPECT_EQ(t["part"]["d"][1].value<double>(), 3.0);  // an integer where the scenario has floats
  EXPECT_TRUE(t["part"]["d"][1].is_floating_point());
  EXPECT_EQ(t["part"]["steps"][0]["depth_mm"].value<double>(), 2.5);
  EXPECT_EQ(t["cut"]["rpm"].value<std::int64_t>(), 450);  // a key the scenario leaves out
  EXPECT_FALSE(t.contains("compare") || t.contains("sweep") || t.contains("study"));
  // A value of another type replaces the scenario's (the reader judges it); an array or table is
  // not a value.
  const auto t2 = toml::parse(apply(base, "t", {"part.new", "run.duration_s"},
                                    {Value{std::int64_t{3}}, Value{std::string("x")}}));
  EXPECT_EQ(t2["part"]["new"].value<std::int64_t>(), 3);
  EXPECT_EQ(t2["run"]["duration_s"].value<std::string>(), "x");
  EXPECT_THROW(apply(base, "t", {"part.d"}, {Value{1.0}}), io::InputError);
  EXPECT_THROW(apply(base, "t", {"part"}, {Value{1.0}}), io::InputError);
  EXPECT_THROW(apply(base, "t", {"part.d[2]"}, {Value{1.0}}), io::InputError);
  EXPECT_THROW(apply(base, "t", {"run.duration_s.x"}, {Value{1.0}}), io::InputError);
  // Every example's values survive the round trip unchanged.
  for (const auto& e : fs::directory_iterator(fs::path(kScenario).parent_path())) {
    if (e.path().extension() != ".toml") continue;
    const std::string src = io::read_scenario_text(e.path().string());
    auto a = toml::parse(src);
    for (const char* s : kStudyTables) a.erase(s);
    EXPECT_EQ(toml::parse(apply(src, "t", {}, {})), a) << e.path();
  }
}

TEST(SweepCases, ValuesAreCheckedByTheScenariosReader) {
  const auto lib = io::MaterialLibrary::load_default();
  const std::string text = io::read_scenario_text(kScenario);
  auto check = [&](const std::string& grid) -> std::string {
    const auto s = parse_spec("scenario = \"" + kScenario + "\"\n[grid]\n" + grid, "s.toml");
    try {
      check_values(s, text, draw_values(s), lib);
    } catch (const io::InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(check("\"controller.feed_mm_per_min\" = [50, 70]\n"), "");
  EXPECT_EQ(check("\"slide.mas_kg\" = [50]\n").rfind("s.toml:3:", 0), 0u);
  EXPECT_EQ(check("\"cut.rpm\" = [50]\n").rfind("s.toml:3:", 0), 0u);  // A has no [cut]
  EXPECT_NE(check("\"compare.controller\" = [\"fim\"]\n").find("studies"), std::string::npos);
  const auto e = check("\"controller.feed_mm_per_min\" = [50,\n -5]\n");
  EXPECT_EQ(e.rfind("s.toml:4:", 0), 0u) << e;
  EXPECT_NE(e.find("key 'controller.feed_mm_per_min' = -5: expected a number"), std::string::npos)
      << e;
}

TEST(SweepStore, ACaseIsRecordedOnceAndAnotherSweepIsRefused) {
  const fs::path dir = fs::temp_directory_path() / ("sweep_store_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::vector<Case> cases = {{0, "a = 1\n", "/b", "{\"a.b\":1}"},
                                   {1, "a = 2\n", "/b", "{\"a.b\":2}"}};
  {
    Store st(dir / "sweep.sqlite");
    st.fill_or_check(cases, "s.toml");
    EXPECT_TRUE(st.record({1, "ok", "", 0.5, std::string("{}")}));
    EXPECT_FALSE(st.record({1, "error", "again", 0.1, std::nullopt}));
  }
  Store st(dir / "sweep.sqlite");
  st.fill_or_check(cases, "s.toml");  // the same cases: accepted
  EXPECT_EQ(st.done(), std::set<std::int64_t>{1});
  const auto r = st.results();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].status, "ok");
  EXPECT_EQ(r[0].summary, std::optional<std::string>("{}"));
  auto changed = cases;
  changed[1].vars = "{\"a.b\":3}";
  EXPECT_THROW(st.fill_or_check(changed, "s.toml"), io::InputError);
  changed.pop_back();
  changed[0] = cases[0];
  EXPECT_THROW(st.fill_or_check(changed, "s.toml"), io::InputError);
  fs::remove_all(dir);
}

TEST(SweepOutputs, MetricsAreTheNumericScalarsByTheirPath) {
  const auto m = metrics_of(
      R"({"system": "B", "metrics": {"a": 1.5, "b": {"with": 2, "without": null}, "c": "x",)"
      R"( "d": [1, 2], "e": {"f": {"g": -3e-7}}}})");
  const std::vector<std::pair<std::string, double>> want = {
      {"a", 1.5}, {"b.with", 2.0}, {"e.f.g", -3e-7}};
  EXPECT_EQ(m, want);
}

// Random specs over an example: each either refused at one of its own lines (io::InputError) or
// made into cases whose texts hold the drawn values bit for bit at their keys.
TEST(SweepGenerated, RandomSpecsAreRefusedAtTheirLinesOrMadeExactly) {
  const auto lib = io::MaterialLibrary::load_default();
  const std::string text = io::read_scenario_text(kScenario);
  const auto root = toml::parse(text);
  std::vector<std::pair<std::string, double>> keys;  // the example's float keys and values
  for (const auto& [t, n] : root)
    if (const auto* tbl = n.as_table(); tbl && t.str() != "compare" && t.str() != "sweep")
      for (const auto& [k, v] : *tbl)
        if (const auto* f = v.as_floating_point())
          keys.emplace_back(std::string(t.str()) + "." + std::string(k.str()), f->get());
  ASSERT_GT(keys.size(), 20u);
  std::mt19937_64 g(45);
  int refused = 0, made = 0;
  for (int iter = 0; iter < 25; ++iter) {
    std::ostringstream spec;
    spec << std::setprecision(17) << "scenario = \"" << kScenario << "\"\n[grid]\n";
    std::vector<std::string> used;
    const auto pick = [&] {
      for (;;) {
        const auto& k = keys[g() % keys.size()];
        if (std::find(used.begin(), used.end(), k.first) == used.end()) {
          used.push_back(k.first);
          return k;
        }
      }
    };
    const auto scale = [&] { return -0.5 + static_cast<double>(g() % 2000) / 1000.0; };
    for (std::uint64_t i = 0, n = 1 + g() % 2; i < n; ++i) {
      const auto [k, v] = pick();
      spec << "\"" << k << "\" = [" << v * scale() << ", " << v * scale() << "]\n";
    }
    spec << "[random]\nsamples = 2\nseed = " << iter << "\n";
    const auto [rk, rv] = pick();
    spec << "\"" << rk << "\" = { uniform = [" << rv * 0.9 << ", " << rv * 1.1 + 1e-9 << "] }\n";
    const auto s = parse_spec(spec.str(), "gen.toml");
    const auto values = draw_values(s);
    try {
      check_values(s, text, values, lib);
    } catch (const io::InputError& e) {
      const std::string what = e.what();
      bool at_a_key = false;
      for (const auto& k : s.varied_keys())
        at_a_key |= what.find("key '" + k + "' = ") != std::string::npos &&
                    what.rfind("gen.toml:", 0) == 0;
      EXPECT_TRUE(at_a_key) << what << "\n" << spec.str();
      ++refused;
      continue;
    }
    const auto cases = make_cases(s, text, values);
    ASSERT_EQ(cases.size(), values.size());
    const auto names = s.varied_keys();
    for (std::size_t c = 0; c < cases.size(); ++c) {
      const auto t = toml::parse(cases[c].scenario);
      for (std::size_t k = 0; k < names.size(); ++k) {
        const auto dot = names[k].find('.');
        const auto got = t[names[k].substr(0, dot)][names[k].substr(dot + 1)].value<double>();
        const auto* i = std::get_if<std::int64_t>(&values[c][k]);  // "0" is written as 0
        EXPECT_EQ(got, i ? static_cast<double>(*i) : std::get<double>(values[c][k])) << names[k];
      }
    }
    ++made;
  }
  EXPECT_GT(made, 5);
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace lathectl::sweep
