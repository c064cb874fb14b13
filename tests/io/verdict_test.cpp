// What went wrong in a run, said everywhere (include/lathectl/io/verdict.hpp): unmet claims,
// alarms and unfinished parts on the console line, in summary.json, atop the report with an
// anchor per claim and in the demo index; and the silent successes it replaced: an E part never
// cut got ✔ for "overshoot −100 %", B ran a step of 5 ms against a 228 Hz chatter, and `lobes`
// stopped at N = 39 on a 650 Hz mode from 500 rpm, leaving inf below ~1000 rpm.
#include "lathectl/io/verdict.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

using namespace lathectl;
using namespace lathectl::io;
using lathectl::systems::b_chatter::lobes_needed;
using lathectl::systems::b_chatter::LobesInput;
using lathectl::systems::b_chatter::parse_lobes_input;

namespace {
using lathectl::test::library;
std::string example(const std::string& name) {
  std::ifstream in(LATHECTL_SOURCE_DIR "/examples/scenarios/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
std::string replace_line(std::string text, const std::string& key, const std::string& line) {
  return std::regex_replace(text, std::regex("\n" + key + " = [^\n]*"), "\n" + line);
}
}  // namespace

TEST(Verdict, ReadsClaimsAlarmsAndUnfinishedPartsFromTheSummary) {
  const auto s = nlohmann::json::parse(R"J({
    "label": "seed 004",
    "claims": [{"claim": "a: first (≥ 1)", "value": 2, "met": true},
               {"claim": "run X: second one (≤ 3)", "value": 4, "met": false}],
    "metrics": {"finished": false,
                "alarms": [{"time_s": 0.1, "code": 7, "reason": "sensor_stuck"}]},
    "comparisons": [{"label": "fixed", "metrics": {"finished": true}}]})J");
  const Verdict v = verdict_of(s);
  EXPECT_EQ(v.claims, 2u);
  ASSERT_EQ(v.unmet.size(), 1u);
  EXPECT_EQ(v.unmet[0].index, 1u);
  EXPECT_FALSE(v.ok());
  // The claims are model checks: reported after the verdict, never deciding it.
  EXPECT_EQ(v.line(),
            "✘ alarm sensor_stuck (code 7) at 0.1 s · part not finished (seed 004) · "
            "model checks: 1 of 2 met (not met: run X: second one)");
  EXPECT_EQ(v.line(false), "✘ 1 alarm · part not finished · model checks: 1 of 2 met");
  EXPECT_EQ(v.json()["claims_met"], 1);
  EXPECT_EQ(
      verdict_of(nlohmann::json::parse(R"({"claims": [{"claim": "c", "met": true}]})")).line(),
      "✔ no acceptance criteria, no alarms · model checks: 1 of 1 met");
}

TEST(Verdict, ReportAnchorsEachClaimAndIndexLinksTheUnmetOnes) {
  Report r;
  r.title = "t";
  r.notes = {"✔ a: 1", "a note", "✘ b: 2"};
  r.note_ids = {"claim-0", "", "claim-1"};
  r.verdict = "✘ 1 of 2 claims not met";
  r.verdict_ok = false;
  r.verdict_items = {{"✘ b", "#claim-1"}};
  const std::string html = render_html(r);
  EXPECT_NE(html.find("<li id=\"claim-1\">✘ b: 2</li>"), std::string::npos);
  EXPECT_NE(html.find("<li>a note</li>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"#claim-1\">✘ b</a>"), std::string::npos);
  EXPECT_LT(html.find("id=\"verdict\""), html.find("<h2>Notes</h2>"));

  IndexEntry bad;
  bad.title = "b";
  bad.href = "b/report.html";
  bad.status = -1;
  bad.problems = {{"✘ b", "b/report.html#claim-1"}};
  IndexEntry good;
  good.title = "g";
  good.href = "g/report.html";
  good.status = 1;
  const std::string index = render_index_html("demo", {bad, good});
  EXPECT_NE(index.find("<span class=\"mark bad\">✘</span>"), std::string::npos);
  EXPECT_NE(index.find("<span class=\"mark ok\">✔</span>"), std::string::npos);
  EXPECT_NE(index.find("<a href=\"b/report.html#claim-1\">✘ b</a>"), std::string::npos);
}

TEST(Verdict, EPartNeverCutMeetsNoForceClaim) {
  // 0.1 s: the tool is still in its approach (its nose meets the blank at 0.18 s). Before: "largest force above its limit: −100 %"
  // was ✔ (−100 ≤ 15) and the console line said nothing.
  const std::string text =
      replace_line(example("e_stepped_seed004.toml"), "duration_s", "duration_s = 0.1");
  const Scenario sc = systems::parse_scenario(text, "e.toml", library());
  const RunOutput out = systems::run_scenario(sc);
  ASSERT_EQ(out.summary["metrics"]["time_in_cut_s"].get<double>(), 0.0);
  int force_claims = 0;
  for (const auto& c : out.summary["claims"]) {
    const std::string t = c["claim"];
    if (t.find("per-revolution") == std::string::npos) continue;
    ++force_claims;
    EXPECT_FALSE(c["met"].get<bool>()) << t;
    EXPECT_TRUE(c["value"].is_null()) << t;
  }
  EXPECT_EQ(force_claims, 4);  // two claims × the two adaptive controllers
  EXPECT_FALSE(out.verdict.ok());
  EXPECT_EQ(out.verdict.unfinished.size(), 3u);
  EXPECT_NE(out.verdict.line().find("part not finished"), std::string::npos);
  EXPECT_EQ(out.summary["verdict"]["ok"], false);
}

TEST(Verdict, BRefusesAStepTooCoarseForItsChatter) {
  const std::string good = example("b_twin_feed_division.toml");
  const Scenario sc = systems::parse_scenario(good, "b.toml", library());
  double f = 0.0;
  const double lim = systems::b_chatter::Rig::max_step_s(sc.get<systems::b_chatter::Settings>().rig, &f);
  // The 600 × 40 mm part's first mode, 226 Hz, chatters near f·√(1+2ζ); ω·dt ≤ 0.2.
  EXPECT_NEAR(f, 227.6, 1.0);
  EXPECT_NEAR(lim, 0.2 / (2 * M_PI * f), 1e-12);
  EXPECT_GT(lim, 2e-5);  // the examples' step passes
  std::string coarse = replace_line(good, "step_s", "step_s = 0.005");
  coarse = replace_line(coarse, "record_interval_s", "record_interval_s = 0.005");
  try {
    (void)systems::parse_scenario(coarse, "b.toml", library());
    ADD_FAILURE() << "a 5 ms step was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("b.toml:18:10: key 'run.step_s'"), std::string::npos) << m;
    EXPECT_NE(m.find("step_s ≤ 0.000139 s"), std::string::npos) << m;
  }
}

TEST(Verdict, LobesReachMinRpmByDefaultAndATooSmallMaxLobesIsAnError) {
  const std::string machine =
      "[cutting]\nkf_N_per_mm2 = 1000\n[[mode]]\nstiffness_N_per_m = 5e7\n"
      "damping_ratio = 0.03\nnatural_frequency_Hz = 650\n[speed]\nmin_rpm = 500\n"
      "max_rpm = 4000\n";
  const LobesInput in = parse_lobes_input(machine, "m.toml");
  // 60·650·√1.06/500 = 80.3 → 81, + 2.
  EXPECT_EQ(in.max_lobes, 83);
  EXPECT_EQ(lobes_needed(in), 83);
  const auto fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm,
                                                   in.max_lobes, 40000);
  // Before (40 lobes): nothing below 1010 rpm, the envelope inf there.
  EXPECT_TRUE(std::isfinite(dynamics::envelope_depth(fd, 600.0)));
  EXPECT_TRUE(std::isfinite(dynamics::envelope_depth(fd, 900.0)));
  int edge = 0;
  for (const auto& l : fd.lobes)
    if (!l.minimum_inside) {
      ++edge;
      const bool at_edge = std::abs(l.minimum.speed_rpm - 500.0) < 5.0 ||
                           std::abs(l.minimum.speed_rpm - 4000.0) < 40.0;
      EXPECT_TRUE(at_edge) << l.N << " " << l.minimum.speed_rpm;
    }
  EXPECT_GT(edge, 0);
  EXPECT_LT(edge, 6);
  try {
    (void)parse_lobes_input(machine + "[lobes]\nmax_lobes = 40\n", "m.toml");
    ADD_FAILURE() << "max_lobes = 40 was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("key 'lobes.max_lobes'"), std::string::npos) << m;
    EXPECT_NE(m.find("at least 83"), std::string::npos) << m;
  }
}
