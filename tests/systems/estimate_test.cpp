// What `lathectl check` says a scenario will cost (systems/estimate.hpp): the steps and parts are
// counted from the scenario exactly as the study makes them; the CPU time follows from them (its
// constants are measured, see docs/scenario-reference.md), so it scales as they do.
#include "systems/estimate.hpp"

#include <gtest/gtest.h>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/registry.hpp"

namespace lathectl {
namespace {

io::Scenario parsed(const std::string& text) {
  return systems::parse_scenario(text, "mem.toml", test::library());
}

TEST(Estimate, CountsTheRunsAStudyMakes) {
  // a_finishing_aim: the run, its uncontrolled comparison and five K_leak factors: 7 runs of
  // 12 s / 1e-4 s.
  const auto e = systems::estimate(parsed(test::example_text("a_finishing_aim")));
  EXPECT_DOUBLE_EQ(e.simulated_steps, 7.0 * 120000.0);
  EXPECT_FALSE(e.upper_bound);
}

TEST(Estimate, ADayOfSystemAIsSaidToBeLong) {
  // (a day at 1e-4 s would be 8.6e8 steps, past the 5e8 a run may have)
  const auto text = test::edited(
      test::edited(test::example_text("a_finishing_aim"), "duration_s = 12.0", "duration_s = 86400.0"),
      "step_s = 1e-4", "step_s = 2e-4");
  const auto day = systems::estimate(parsed(text));
  const auto base = systems::estimate(parsed(test::example_text("a_finishing_aim")));
  EXPECT_DOUBLE_EQ(day.simulated_steps / base.simulated_steps, 3600.0);
  EXPECT_NEAR(day.cpu_s / base.cpu_s, 3600.0, 1e-6 * 3600.0);
  EXPECT_GT(day.output_bytes, 100.0 * base.output_bytes);
  EXPECT_NE(systems::summary_text(day).find(" min of CPU"), std::string::npos)
      << systems::summary_text(day);
}

TEST(Estimate, MonteCarloPartsScaleTheGauge) {
  const auto few = systems::estimate(parsed(test::example_text("d_gauging")));
  const auto many = systems::estimate(parsed(
      test::edited(test::example_text("d_gauging"), "parts = 100000", "parts = 10000000")));
  EXPECT_DOUBLE_EQ(few.parts, 100000.0 + 8.0);
  EXPECT_DOUBLE_EQ(many.parts, 10000000.0 + 8.0);
  EXPECT_GT(many.cpu_s, 50.0 * few.cpu_s);
  EXPECT_GT(many.output_bytes, 50.0 * (few.output_bytes - 1e6));
}

TEST(Estimate, AdaptiveRunsAreUpperBounds) {
  const auto e = systems::estimate(parsed(test::example_text("e_stepped_seed004")));
  EXPECT_TRUE(e.upper_bound);
  EXPECT_NE(systems::summary_text(e).find("at most"), std::string::npos);
}

// A's regulator studies are counted (issue 49: check left them out, 17–21× low): the tolerance
// Monte Carlo's 6 draws of `samples` regulators of 600 steps, the obliteration study's
// 1 + |η| + 2·|layers| regulators over the run at a quarter pulse period a step.
TEST(Estimate, CountsARegulatorStudies) {
  const auto base = systems::estimate(parsed(test::example_text("a_regulator_switching")));
  const auto many = systems::estimate(parsed(
      test::edited(test::example_text("a_regulator_switching"), "samples = 400", "samples = 40000")));
  EXPECT_NEAR(many.cpu_s - base.cpu_s, 6.0 * (40000.0 - 400.0) * 600.0 * 14e-9, 1e-9);
  const auto ob = systems::estimate(parsed(test::example_text("a_obliteration")));
  EXPECT_NE(ob.breakdown.find("obliteration study 21 regulators × 1.4e+05 steps"), std::string::npos)
      << ob.breakdown;
}

// E counts the runs beside the comparison as run_beside makes them: seed004 (fixed, prior art,
// seed law) adds the prior art at the seed's tool budget, so 4 runs, not 3.
TEST(Estimate, CountsTheRunsBesideAdaptiveRuns) {
  const auto e = systems::estimate(parsed(test::example_text("e_stepped_seed004")));
  const auto one = systems::estimate(parsed(test::example_text("e_stepped_fixed")));
  EXPECT_DOUBLE_EQ(e.simulated_steps, 4.0 * one.simulated_steps);
}

}  // namespace
}  // namespace lathectl
