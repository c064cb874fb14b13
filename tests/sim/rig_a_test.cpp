// Closed-loop checks of rig A (seed 000) on the example scenarios: the seed's claims measured in
// simulation, and the uncontrolled slide's feed loss against the seed's own formula (3).
// a_obliteration (1800 s of simulated time) is deliberately not run here.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/a_pulse_feed/metrics.hpp"
#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl::systems::a_pulse_feed {
namespace {

using lathectl::test::library;

io::Scenario scenario(const std::string& name) {
  return systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/scenarios/" + name + ".toml",
                                library());
}

// The scenario's rig configuration (system A's settings).
const RigConfig& config(const io::Scenario& sc) {
  return sc.get<Settings>().rig;
}

// The claim whose text starts with `prefix` (summary["claims"]): its value, threshold and verdict.
const nlohmann::json& claim(const nlohmann::json& summary, const std::string& prefix) {
  for (const auto& c : summary["claims"])
    if (c["claim"].get<std::string>().rfind(prefix, 0) == 0) return c;
  ADD_FAILURE() << "no claim starting with: " << prefix;
  static const nlohmann::json none = nlohmann::json::object();
  return none;
}

void run_rig(const io::Scenario& sc, const RigConfig& cfg, Rig& rig) {
  rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  rig.run();
  ASSERT_TRUE(rig.numerically_sound());
}

TEST(Rig, FinishingAimHoldsFeedFiveTimesBetterThanUncontrolled) {
  const auto sc = scenario("a_finishing_aim");
  const auto out = systems::run_scenario(sc);
  const auto& s = out.summary;
  ASSERT_TRUE(s.contains("comparison"));
  const double controlled = s["metrics"]["feed_rate_deviation_pct"].get<double>();
  const double uncontrolled = s["comparison"]["metrics"]["feed_rate_deviation_pct"].get<double>();
  // Seed claim 1 (finishing): the deviation under the force change is much smaller with control;
  // "much" made concrete as at most a fifth.
  EXPECT_GT(uncontrolled, 5.0);  // the disturbance really disturbs (≈ 12 %)
  // The claim's threshold is data in the summary: read, not typed again here.
  const auto& max_claim = claim(s, "finishing: max feed deviation");
  ASSERT_TRUE(max_claim.contains("threshold"));
  EXPECT_LE(controlled, max_claim["threshold"].get<double>() * uncontrolled)
      << controlled << " % vs " << uncontrolled << " %";
  EXPECT_TRUE(max_claim["met"].get<bool>());
  // The force did change: the allowance doubles, Py ∝ t^0.9 → ≈ ×1.87.
  EXPECT_GT(s["metrics"]["force_peak_N"].get<double>(),
            1.5 * s["metrics"]["force_nominal_N"].get<double>());
  // Steady state: the controlled feed returns to its reference.
  const auto& steady_claim = claim(s, "finishing: steady feed deviation");
  ASSERT_TRUE(steady_claim.contains("threshold"));
  EXPECT_LT(s["metrics"]["feed_rate_steady_deviation_pct"].get<double>(),
            steady_claim["threshold"].get<double>() *
                s["comparison"]["metrics"]["feed_rate_steady_deviation_pct"].get<double>());
}

TEST(Rig, UncontrolledFeedLossMatchesSeedFormula3) {
  const auto sc = scenario("a_finishing_aim");
  RigConfig cfg = config(sc);
  cfg.controller_kind = ControllerKind::None;
  Rig rig;
  run_rig(sc, cfg, rig);
  const auto m = compute_metrics(rig);
  const auto& rec = rig.recorder();
  const auto t = rec.column("time_s");
  const auto force = rec.column("force_Py_N");
  const double T = t.back();
  const double td = rig.first_disturbance_time();
  ASSERT_GT(td, 1.0);
  // ΔP: mean radial force over the last 10 % of the run (where the steady deviation is measured)
  // minus the mean over the second before the disturbance (where S_ref is measured).
  const double p_before = sim::mean_between(t, force, td - 1.0, td);
  const double p_after = sim::mean_between(t, force, 0.9 * T, T + 1.0);
  const double dP = p_after - p_before;
  EXPECT_GT(dP, 50.0);
  // Seed (3): S = Q/F − K_leak·Py/F² at constant Q, so ΔS = −K_leak·ΔPy/F².
  const double F = config(sc).slide.piston_area_m2;
  const double K = config(sc).slide.leak_m3_per_s_Pa;
  const double dS_pct = 100.0 * (K * dP / (F * F)) / (m.feed_rate_reference_mm_per_min / 60000.0);
  // With ΔPy ≈ 85 N: 8.333e−13·85/6.4e−7 = 1.1e−4 m/s = 6.6 mm/min of 58.5, ≈ 11 %.
  EXPECT_NEAR(m.feed_rate_steady_deviation_pct, dS_pct, 0.15 * dS_pct)
      << "simulated " << m.feed_rate_steady_deviation_pct << " %, formula (3) " << dS_pct << " %";
  // Closer: the slide also has viscous friction b, whose load b·S falls with the feed, so
  // ΔS = K·ΔPy/F² / (1 + K·b/F²); here K·b/F² = 8.333e−13·2e4/6.4e−7 = 0.026.
  const double b = config(sc).slide.viscous_friction_N_s_per_m;
  const double dS_visc_pct = dS_pct / (1.0 + K * b / (F * F));
  EXPECT_NEAR(m.feed_rate_steady_deviation_pct, dS_visc_pct, 0.02 * dS_visc_pct);
  // And it is a loss: the feed falls.
  const auto feed = rec.column("feed_mm_per_min");
  EXPECT_LT(sim::mean_between(t, feed, 0.9 * T, T + 1.0), m.feed_rate_reference_mm_per_min);
}

// Regression (found by this test, fixed): The uncontrolled slot is "set once for
// the programmed feed at the nominal force" (a_finishing_none.toml), but Rig::configure computes
// it from q = S·F + K_leak·(P + F_c)/F without the viscous friction b·S (20000 N·s/m · 1 mm/s = 20
// N here), and the controller's load model (friction_N = F_c only) leaves it out too. The slide
// then runs 2.4–2.6 % below the programmed feed before any disturbance, with or without control
// (a_regulator_flow: 58.61 mm/min for 60; the predicted shortfall is K_leak·b·S/F² = 2.6 %).
TEST(Rig, UndisturbedSlideRunsAtProgrammedFeed) {
  const auto sc = scenario("a_regulator_flow");
  const auto out = systems::run_scenario(sc);
  const double programmed = out.summary["metrics"]["feed_rate_programmed_mm_per_min"].get<double>();
  const double mean = out.summary["metrics"]["feed_rate_mean_mm_per_min"].get<double>();
  EXPECT_NEAR(mean, programmed, 0.005 * programmed);
}

// The tool's wear account against its closed form. Where the material's extended Taylor law
// has y_v/m = 1 (steel_45 up to 0.3 mm/rev: y_v = 0.20, m = 0.2), T = A/s with
// A = (C_v·K_mv/(V·t^x_v))^(1/m), so Σ dt/T = Σ s·dt/A and, s being the travel over the last
// revolution, Σ s·dt = (60/n)·travel: the life used is travel/(n·A) whatever the pulses' ripple.
TEST(Rig, ToolLifeUsedIsTheTravelOverTheTaylorConstantWhereYvOverMIsOne) {
  const auto sc = scenario("a_regulator_flow");
  RigConfig cfg = config(sc);
  cfg.part.runout_mm = 0.0;
  cfg.part.random_sigma_mm = 0.0;
  const auto& law = cfg.cutting.material.tool_life[0];
  ASSERT_NEAR(law.yv / law.m, 1.0, 1e-12) << "the closed form needs y_v/m = 1";
  Rig rig;
  run_rig(sc, cfg, rig);
  const double travel_mm = rig.position() * 1000.0;  // the slide starts at x = 0
  const double s_mean = travel_mm / rig.time() * 60.0 / cfg.spindle_rpm;
  ASSERT_LE(s_mean, law.feed_max_mm_per_rev);
  const double V = std::numbers::pi * cfg.diameter_m * cfg.spindle_rpm;  // m/min
  cutting::CuttingModel cut;
  cut.configure(cfg.cutting);
  const double depth = rig.recorder().column("depth_mm").back();
  // A = T·s at any s of the range (the law is exactly A/s there)
  const double A = cut.tool_life_min(V, 0.1, depth) * 0.1;
  ASSERT_GT(travel_mm, 0.0);
  EXPECT_NEAR(rig.tool_life_used(), travel_mm / (cfg.spindle_rpm * A),
              1e-3 * rig.tool_life_used());
}

TEST(Rig, RoughingAimHoldsForceAtSetValue) {
  const auto sc = scenario("a_roughing_aim");
  const auto out = systems::run_scenario(sc);
  const auto& m = out.summary["metrics"];
  // Seed claim 2: the force is brought back to its set value (355 N).
  ASSERT_FALSE(m["force_final_error_pct"].is_null());
  const auto& force_claim = claim(out.summary, "roughing: force within 5 %");
  ASSERT_TRUE(force_claim.contains("threshold"));
  EXPECT_LE(std::abs(m["force_final_error_pct"].get<double>()),
            force_claim["threshold"].get<double>());
  ASSERT_FALSE(m["force_settling_time_s"].is_null());  // null = never settled
  EXPECT_TRUE(std::isfinite(m["force_settling_time_s"].get<double>()));
  EXPECT_GT(m["force_settling_time_s"].get<double>(), 0.0);
  // Without control the depth step drives Py ≈ (2.16)^0.9 ≈ 2× nominal.
  const auto& c = out.summary["comparison"]["metrics"];
  EXPECT_GE(c["force_peak_N"].get<double>(), 1.6 * c["force_nominal_N"].get<double>());
  // With control the peak stays far below the uncontrolled one.
  EXPECT_LT(m["force_peak_N"].get<double>(), 0.75 * c["force_peak_N"].get<double>());
  // The controller reduced the feed to get there (it never feeds faster than programmed).
  EXPECT_LT(m["feed_rate_mean_mm_per_min"].get<double>(),
            m["feed_rate_programmed_mm_per_min"].get<double>());
}

TEST(Rig, RoughingAimNeverFeedsFasterThanProgrammed) {
  const auto sc = scenario("a_roughing_aim");
  Rig rig;
  run_rig(sc, config(sc), rig);
  const auto& rec = rig.recorder();
  const auto feed = rec.column("feed_mm_per_min");
  const auto t = rec.column("time_s");
  const double programmed = config(sc).controller.feed_m_per_s * 60000.0;
  // The recorded feed is averaged over whole pulse periods; allow 1 % for slide dynamics. The
  // first 0.5 s are skipped, as compute_metrics skips them: the rig starts the pulse train
  // "on" from the mean damper state and the feed overshoots by ~15 % for ~0.1 s (see report).
  double peak = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= 0.5) peak = std::max(peak, feed[i]);
  EXPECT_LE(peak, 1.01 * programmed);
}

TEST(Rig, SensorDropoutAlarmsWithinOnePeriodAndStopsFeed) {
  const auto sc = scenario("a_sensor_dropout");
  ASSERT_EQ(config(sc).faults.size(), 1u);
  const double fault_at = config(sc).faults[0].at_s;
  const auto out = systems::run_scenario(sc);
  const auto& m = out.summary["metrics"];
  ASSERT_GE(m["alarms"].size(), 1u);
  EXPECT_EQ(m["alarms"][0]["code"].get<int>(), 10);  // Reason::SensorNotFinite
  EXPECT_EQ(m["alarms"][0]["reason"].get<std::string>(), "sensor_not_finite");
  ASSERT_FALSE(m["first_alarm_delay_s"].is_null());
  EXPECT_GE(m["first_alarm_delay_s"].get<double>(), 0.0);
  EXPECT_LE(m["first_alarm_delay_s"].get<double>(), config(sc).controller.period_s + 1e-9);  // 1 ms
  EXPECT_NEAR(m["alarms"][0]["time_s"].get<double>(), fault_at, config(sc).controller.period_s + 1e-9);

  // The feed stops: the last recorded feed is below 1 % of the programmed one, and the alarm
  // stays latched to the end.
  Rig rig;
  run_rig(sc, config(sc), rig);
  const auto& rec = rig.recorder();
  const auto feed = rec.column("feed_mm_per_min");
  const auto alarm = rec.column("alarm");
  const auto slot = rec.column("slot_um");
  const double programmed = config(sc).controller.feed_m_per_s * 60000.0;
  EXPECT_LT(std::abs(feed.back()), 0.01 * programmed) << feed.back();
  EXPECT_EQ(alarm.back(), 1.0);
  const auto t = rec.column("time_s");
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < fault_at - 1e-9) {
      ASSERT_EQ(alarm[i], 0.0) << t[i];
    }
    if (t[i] > fault_at + 1e-3) {
      ASSERT_EQ(alarm[i], 1.0) << t[i];
    }
  }
  // The eccentric drove the slot shut.
  EXPECT_LT(slot.back(), 0.5);  // µm
}

TEST(Rig, RegulatorFlowMatchesFormula1) {
  const auto sc = scenario("a_regulator_flow");
  const auto out = systems::run_scenario(sc);
  const auto& m = out.summary["metrics"];
  ASSERT_FALSE(m["flow_formula_error_pct"].is_null());
  EXPECT_LT(std::abs(m["flow_formula_error_pct"].get<double>()), 1.0);
  // Formula (1) at the rig's slot: μπd·h·sqrt(2Δp/ρ)·Δt/T in cm³/min.
  Rig rig;
  rig.configure(config(sc), sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  const double q1 = config(sc).regulator.orifice.gain_per_m() * rig.fixed_actuator() *
                    config(sc).pulse_width_s * config(sc).frequency_Hz * 6e7;
  EXPECT_NEAR(m["flow_formula_cm3_per_min"].get<double>(), q1, 1e-9 * q1);
}

// Oil volume is conserved through cavitation (issue "Results a user can trust", finding 1).
// a_finishing_aim without its damper and with 2000 instead of 20000 N·s/m of viscous friction:
// the light, undamped slide overshoots each pulse and the chamber cavitates. Before the fix the
// pressure was clamped at 0 and the opened void forgotten: here the slide travelled 99.6 mm/min
// on (Q − q_leak)/F = 64.9 mm/min (41 % of the delivered oil unexplained; p = 0 on 8 % of the
// rows). Now the void is refilled before the pressure rises again (p = 0 on 24 % of the rows:
// 63.75 mm/min of travel on 63.87), so
//   ∫(q − q_leak) dt = F·Δx + storage,   mean velocity = (Q − q_leak)/F.
TEST(Rig, UndampedSlideConservesOilThroughCavitation) {
  std::ifstream in(LATHECTL_SOURCE_DIR "/examples/scenarios/a_finishing_aim.toml", std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto pos = text.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
  };
  replace("damper_capacitance_cm3_per_MPa = 0.5", "damper_capacitance_cm3_per_MPa = 0.0");
  replace("viscous_friction_N_s_per_m = 20000.0", "viscous_friction_N_s_per_m = 2000.0");
  const auto sc = systems::parse_scenario(text, "a_undamped.toml", library());
  Rig rig;
  run_rig(sc, config(sc), rig);
  const auto& rec = rig.recorder();
  const auto t = rec.column("time_s");
  const auto x = rec.column("travel_mm");
  const auto flow = rec.column("flow_cm3_per_min");
  const auto leak = rec.column("leak_cm3_per_min");
  const auto p = rec.column("cylinder_pressure_MPa");
  ASSERT_GT(t.size(), 100u);
  std::size_t zero = 0;
  double q = 0.0, l = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    zero += p[i] == 0.0 ? 1 : 0;
    q += flow[i];  // mean over each record interval: exact
    l += leak[i];  // sampled (0 while cavitated)
  }
  q /= static_cast<double>(t.size());
  l /= static_cast<double>(t.size());
  EXPECT_GT(zero, t.size() / 20) << "the scenario should cavitate";
  const double area_cm2 = config(sc).slide.piston_area_m2 * 1e4;
  const double v_mm_per_min = x.back() / t.back() * 60.0;
  const double v_flow = (q - l) / area_cm2 * 10.0;  // cm/min → mm/min
  EXPECT_NEAR(v_mm_per_min, v_flow, 0.005 * v_flow)
      << "travel " << v_mm_per_min << " mm/min, (Q − q_leak)/F " << v_flow << " mm/min";
  // The rig's exact ledger: the net inflow explains the travel to 0.5 % of the delivered oil,
  // and no oil is made or lost (to rounding).
  const auto b = rig.volume_balance();
  EXPECT_LT(b.travel_unexplained_pct, 0.5);
  EXPECT_LT(b.conservation_error_pct, 1e-6);
  EXPECT_NEAR(b.delivered_m3 - b.leaked_m3, b.swept_m3 + b.stored_m3, 1e-8 * b.delivered_m3);
}

}  // namespace
}  // namespace lathectl::systems::a_pulse_feed
