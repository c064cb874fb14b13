// System D's safety and accuracy: the check refuses a threshold outside the signal
// range the full model reaches, force_threshold lets it through, the backstop ends any cut the
// relay does not, the filtered linearised Monte Carlo against the extended (25), and the dynamic
// calibration on the full model.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <numeric>
#include <sstream>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/d_gauging/rig.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl {
namespace {

using test::edited;
using test::library;
std::string example(const std::string& name) { return test::example_text(name); }

// The new user: the d_gauging example with allowance 290 µm and a target near A0
// (254 µm = 0.85·A0), on the seed's transducer (lightly damped contact, first-order filter, the
// linear coil): (23) with the seed's line and with the calibrated one both fall below the
// probe's bounce floor. On the example's own transducer (damped contact: a lower floor) the
// calibrated threshold is reachable and only the seed's is refused.
TEST(SystemDSafety, ThresholdBelowTheBounceFloorIsRefusedAtTheTarget) {
  std::string t = edited(example("d_gauging"), "allowance_um = 250.0", "allowance_um = 290.0");
  t = edited(t, "target_um = 100.0", "target_um = 254.0");
  std::string seed_tr =
      edited(t, "contact_damping_N_s_per_m = 200.0", "contact_damping_N_s_per_m = 5.0");
  seed_tr = edited(seed_tr, "filter = \"synchronous\"\n", "");
  seed_tr = edited(seed_tr, "magnet_gap_mm = 4.739", "magnet_gap_mm = 0.0");
  auto refused = [](const std::string& text, const char* kind) {
    const std::string k =
        edited(text, "threshold = \"calibrated\"", std::string("threshold = \"") + kind + "\"");
    try {
      (void)io::parse_scenario(k, "mem.toml", library(), systems::d_gauging::kSection);
      ADD_FAILURE() << kind << ": not refused";
    } catch (const io::InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("process.target_um"), std::string::npos) << msg;
      EXPECT_NE(msg.find("bounce floor"), std::string::npos) << msg;
      EXPECT_NE(msg.find("force_threshold"), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    }
  };
  refused(seed_tr, "seed");
  refused(seed_tr, "calibrated");
  refused(t, "seed");
  EXPECT_NO_THROW((void)io::parse_scenario(t, "mem.toml", library(), systems::d_gauging::kSection));
  // Forced, it parses; the example near A0 is that set-up.
  EXPECT_NO_THROW((void)io::parse_scenario(example("d_near_a0"), "mem.toml", library(),
                                           systems::d_gauging::kSection));
}

TEST(SystemDSafety, GivenThresholdAboveTheFreeSignalIsRefusedAtItsKey) {
  std::string t = edited(example("d_gauging"), "threshold = \"calibrated\"",
                         "threshold = \"given\"\nthreshold_V = 50.0");
  try {
    (void)io::parse_scenario(t, "mem.toml", library(), systems::d_gauging::kSection);
    ADD_FAILURE() << "not refused";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gauge.threshold_V"), std::string::npos) << e.what();
  }
}

TEST(SystemDSafety, ExamplesThresholdsLieInTheSafeRange) {
  for (const char* name : {"d_gauging", "d_low_resonance"}) {
    const auto sc =
        io::parse_scenario(example(name), "mem.toml", library(), systems::d_gauging::kSection);
    const auto& d = sc.get<systems::d_gauging::Settings>();
    const auto plan = systems::d_gauging::plan_threshold(d, sc.run.step_s);
    EXPECT_TRUE(plan.safe()) << name;
    // The floor at the start of the cut is about 1-2 V, not (20)'s K·(A0 − x).
    EXPECT_GT(plan.range.floor_V, 0.9) << name;
    EXPECT_LT(plan.range.floor_V, 2.0) << name;
    EXPECT_GT(plan.largest_target_m, d.process.target_m) << name;
    EXPECT_LT(plan.largest_target_m, d.process.allowance_m) << name;
    // Default backstop: the lower tolerance limit.
    EXPECT_NEAR(d.process.backstop_m, d.process.target_m - d.tolerance_m, 1e-15) << name;
  }
}

systems::d_gauging::GaugingProcess process() {
  systems::d_gauging::GaugingProcess p;
  p.allowance_m = 250e-6;
  p.removal_m_per_s = 20e-6;
  p.target_m = 100e-6;
  p.noise_variance_m2 = 4e-12;
  p.backstop_m = 90e-6;
  return p;
}

TEST(SystemDBackstop, EndsTheLinearCutsTheRelayDoesNot) {
  const auto p = process();
  const systems::d_gauging::LinearGauge g{19844.0, 298e-6, 0.1};
  const auto parts =
      systems::d_gauging::monte_carlo_linear(p, g, 100.0, 200, 5);  // S_th never reached
  for (const auto& r : parts) {
    EXPECT_TRUE(r.backstop);
    EXPECT_TRUE(std::isnan(r.trip_s));
    EXPECT_NEAR(r.finished_m, p.backstop_m, 1e-12);
  }
}

TEST(SystemDBackstop, EndsTheFullModelCutAtItsLimit) {
  auto p = process();
  p.noise_variance_m2 = 0.0;
  sensors::VibroContactGauge::Params gp;
  const auto r = systems::d_gauging::machine_part_full(p, gp, 2e-5, 100.0, 1, nullptr, 50, 12.0);
  EXPECT_TRUE(r.backstop);
  EXPECT_NEAR(r.finished_m, p.backstop_m, 1e-12);
  EXPECT_NEAR(r.stop_s, (p.allowance_m - p.backstop_m) / p.removal_m_per_s, 1e-12);
}

// The linearised Monte Carlo of the second-order and synchronous filters against (25) extended
// to them (VibroContactGauge::filter_noise_factor): the size scatter σ_x = sqrt(D·f).
TEST(SystemDFilters, LinearMonteCarloScatterMatchesExtended25) {
  using F = sensors::VibroContactGauge::Params::Filter;
  const auto p = process();
  for (F f : {F::SecondOrder, F::Synchronous}) {
    systems::d_gauging::LinearGauge g{19844.0, 298e-6, 0.1, f, 50.0};
    const double th = systems::d_gauging::threshold_23(g, p);
    const auto parts = systems::d_gauging::monte_carlo_linear(p, g, th, 20000, 11);
    double m = 0.0, ss = 0.0;
    for (const auto& r : parts) m += r.finished_m;
    m /= static_cast<double>(parts.size());
    for (const auto& r : parts) ss += (r.finished_m - m) * (r.finished_m - m);
    const double sd = std::sqrt(ss / static_cast<double>(parts.size() - 1));
    const double pred = std::sqrt(p.noise_variance_m2 * g.noise_factor(p.noise_beta_per_s));
    // σ of a σ estimate from 2e4 parts: 0.5 %; 3 % leaves room for the step's discretisation.
    EXPECT_NEAR(sd / pred, 1.0, 0.03) << static_cast<int>(f);
    // (23) with the filter's lag: the mean within a few standard errors and the first-passage
    // bias (≈ 0.01 µm) of target.
    EXPECT_NEAR(m, p.target_m, 5.0 * sd / std::sqrt(20000.0) + 0.02e-6) << static_cast<int>(f);
  }
}

// Without noise the dynamic calibration re-aims part by part until the full model is on target.
TEST(SystemDCalibration, DynamicCalibrationWithoutNoiseLandsOnTarget) {
  auto p = process();
  p.noise_variance_m2 = 0.0;
  sensors::VibroContactGauge::Params gp;
  gp.contact_damping_N_s_per_m = 200.0;  // regular probe (the design rule)
  gp.filter = sensors::VibroContactGauge::Params::Filter::SecondOrder;
  const auto st = sensors::VibroContactGauge::steady(gp);
  const systems::d_gauging::LinearGauge g{st.signal_gain_V_per_m, st.free_amplitude_m, 0.1,
                                          gp.filter, gp.supply_Hz};
  const double th0 = systems::d_gauging::threshold_23(g, p) + 0.1;  // started 5 µm off
  const auto c = systems::d_gauging::calibrate_dynamic(p, gp, 2e-5, th0, st.signal_gain_V_per_m, 8,
                                                       0.2e-6, 3, 12.0);
  EXPECT_TRUE(c.converged);
  EXPECT_LE(c.parts, 8u);
  const auto r =
      systems::d_gauging::machine_part_full(p, gp, 2e-5, c.threshold_V, 3, nullptr, 50, 12.0);
  EXPECT_NEAR((r.finished_m - p.target_m) * 1e6, 0.0, 0.1);
}

// The seed's multi-step cycle in the full model: rough → fine → spark-out → size, each threshold
// (23) at the rate of the step it ends; each step's command operates in order and near its
// planned size (a tenth of the step it starts: the static line misses more at the faster feeds),
// the size within a tenth of the tolerance.
TEST(SystemDCycle, StepsOperateInOrderAtTheirPlannedSizes) {
  const auto sc = io::parse_scenario(example("d_cycle_keyway"), "mem.toml", library(),
                                     systems::d_gauging::kSection);
  auto d = sc.get<systems::d_gauging::Settings>();
  d.process.interruption = {};
  d.process.noise_variance_m2 = 0.0;
  const auto plan = systems::d_gauging::plan_threshold(d, sc.run.step_s);
  auto p = d.process;
  const double lag =
      sensors::VibroContactGauge::filter_lag_s(d.transducer) + p.relay_response_s;
  p.cycle = systems::d_gauging::gauging_cycle(d.sequence, plan.line, p, lag, plan.threshold_V);
  ASSERT_EQ(p.cycle.before.size(), 2u);
  const auto r = systems::d_gauging::machine_part_full(p, d.transducer, sc.run.step_s,
                                                       plan.threshold_V, 3, nullptr, 50, 12.0);
  ASSERT_FALSE(r.backstop);
  EXPECT_NEAR(r.step_at_m[0], p.target_m + d.sequence.fine_m, 0.1 * 35e-6);
  EXPECT_NEAR(r.step_at_m[1], p.target_m + d.sequence.spark_m, 0.1 * 25e-6);
  EXPECT_GT(r.step_at_m[0], r.step_at_m[1]);
  EXPECT_GT(r.step_at_m[1], r.finished_m);
  EXPECT_NEAR(r.finished_m, p.target_m, 0.1 * d.tolerance_m);
  // The faster steps shorten the part: rough 4·a, fine 2·a.
  const double t_single = (p.allowance_m - p.target_m) / p.removal_m_per_s;
  EXPECT_LT(r.stop_s, 0.7 * t_single);
}

// Interrupted surfaces in the full model at 600 rpm. A keyway deeper than the probe's free
// amplitude: read as size (no gate) the part ends large; bridged by the machine (its gate, the
// threshold's lag with the bridges' delay) it ends as the round part does. The flats' geometry.
TEST(SystemDInterruption, BridgedKeywayEndsAsTheRoundPart) {
  const auto sc = io::parse_scenario(example("d_cycle_keyway"), "mem.toml", library(),
                                     systems::d_gauging::kSection);
  auto d = sc.get<systems::d_gauging::Settings>();
  d.process.noise_variance_m2 = 0.0;
  auto finished = [&](const systems::d_gauging::Interruption& ir) {
    auto dd = d;
    dd.process.interruption = ir;
    const auto plan = systems::d_gauging::plan_threshold(dd, sc.run.step_s);
    const auto r = systems::d_gauging::machine_part_full(dd.process, dd.transducer, sc.run.step_s,
                                                         plan.threshold_V, 3, nullptr, 50, 12.0);
    EXPECT_FALSE(r.backstop);
    return r.finished_m - dd.process.target_m;
  };
  const double round = finished({});
  auto keyway = d.process.interruption;
  ASSERT_EQ(keyway.kind, systems::d_gauging::Interruption::Kind::Keyway);
  ASSERT_TRUE(keyway.gate);
  EXPECT_NEAR(finished(keyway), round, 0.5e-6);
  keyway.gate = false;
  EXPECT_GT(finished(keyway) - round, 2.0e-6);
  systems::d_gauging::Interruption flats;
  flats.kind = systems::d_gauging::Interruption::Kind::Flats;
  flats.count = 2;
  flats.depth_m = 50e-6;
  flats.radius_m = 10e-3;
  flats.guard_s = 0.01;
  // Each chord spans 2·acos(1 − h/R).
  EXPECT_NEAR(2.0 * flats.half_span_rad() * 180.0 / std::numbers::pi, 11.46, 0.01);
  EXPECT_NEAR(flats.depth_at(0.0), 50e-6, 1e-12);
  EXPECT_EQ(flats.depth_at(std::numbers::pi / 2.0), 0.0);
  EXPECT_TRUE(flats.under(std::numbers::pi + 0.09));  // the second flat, 180° on
  EXPECT_FALSE(flats.under(std::numbers::pi + 0.11));
}

// Flats in the full model (d_cycle_flats: two flats on a 10 mm radius at 150 rpm, the cycle, no
// noise). Bridged with a guard that covers the probe's settling (40 ms and more; its free ring-down
// 2M/h is 29 ms) the part ends as the round part does, within 0.15 µm, for 50 and 100 µm deep
// flats and guards of 40 to 80 ms; read as size it ends more than 1 µm large. At 600 rpm the
// flats come every 50 ms: the check refuses the part at spindle_rpm, saying how fast it may turn.
TEST(SystemDInterruption, BridgedFlatsEndAsTheRoundPartWhenTheProbeSettlesBetweenThem) {
  const auto sc = io::parse_scenario(example("d_cycle_flats"), "mem.toml", library(),
                                     systems::d_gauging::kSection);
  auto d = sc.get<systems::d_gauging::Settings>();
  d.process.noise_variance_m2 = 0.0;
  const auto flats = d.process.interruption;
  ASSERT_EQ(flats.kind, systems::d_gauging::Interruption::Kind::Flats);
  ASSERT_TRUE(flats.gate);
  auto finished = [&](const systems::d_gauging::Interruption& ir) {
    auto dd = d;
    dd.process.interruption = ir;
    const auto plan = systems::d_gauging::plan_threshold(dd, sc.run.step_s);
    auto p = dd.process;
    p.cycle = systems::d_gauging::gauging_cycle(
        dd.sequence, plan.line, p,
        sensors::VibroContactGauge::filter_lag_s(dd.transducer) + p.relay_response_s +
            ir.bridge_lag_s(dd.transducer.supply_Hz),
        plan.threshold_V);
    const auto r = systems::d_gauging::machine_part_full(p, dd.transducer, sc.run.step_s,
                                                         plan.threshold_V, 3, nullptr, 50, 12.0);
    EXPECT_FALSE(r.backstop);
    return r.finished_m - p.target_m;
  };
  const double round = finished({});
  for (const auto& [depth, guard] : {std::pair{100e-6, 0.04}, {100e-6, 0.08}, {50e-6, 0.06}}) {
    auto ir = flats;
    ir.depth_m = depth;
    ir.guard_s = guard;
    EXPECT_NEAR(finished(ir), round, 0.15e-6) << depth << " m, guard " << guard;
  }
  auto open = flats;
  open.gate = false;
  EXPECT_GT(finished(open) - round, 1e-6);
  const std::string fast = edited(example("d_cycle_flats"), "spindle_rpm = 150.0",
                                  "spindle_rpm = 600.0");
  try {
    (void)io::parse_scenario(fast, "mem.toml", library(), systems::d_gauging::kSection);
    ADD_FAILURE() << "600 rpm with two flats and a 60 ms guard was accepted";
  } catch (const io::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("spindle_rpm"), std::string::npos) << msg;
    EXPECT_NE(msg.find("two supply periods"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace lathectl
