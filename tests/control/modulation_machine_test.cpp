// System B's machine side (control::ModulationMachine): the chains and the planner as one object.
// Checked against what each block is by definition (seed 001): the idle compensation stores N_m
// of the idle block and the adder gives N_c = N_m − N_idle (blocks 12–14); the planner gets the
// chain's a0 and ω_d (detectors 19–20) and plans exactly what ModulatedFeedController::plan_for
// gives for them; only the flagged turret's feed moves; without an idle reference no plan.

#include "lathectl/control/modulation_machine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lathectl/core/parameter_error.hpp"

namespace {

using namespace lathectl::control;

ModulationMachine::Params quiet_params() {
  ModulationMachine::Params p;
  p.vibration.noise_m = 0.0;          // the detectors' readings exact
  p.power.meter = {1e-6, 0.0, 1e6, 2};  // no lag, no noise: N_m exact
  p.module.period_s = 1e-3;
  return p;
}

ModulationMachine::Input cutting(double motor_W) {
  ModulationMachine::Input in;
  in.motor_power_W = motor_W;
  in.rpm = 800.0;
  in.speed_m_per_min = 100.0;
  in.feed_requested = 2.0;  // G94: 2 mm/s along the path, 120 mm/min for each turret
  in.feed_block = true;
  return in;
}

// 10 sensor samples per control period of a 230 Hz vibration of amplitude amp [m].
void vibrate(ModulationMachine& m, int k, double amp) {
  for (int s = 0; s < 10; ++s)
    m.sense(amp * std::sin(2.0 * std::numbers::pi * 230.0 * (k * 10 + s) * 1e-4));
}

}  // namespace

TEST(ModulationMachine, IdleCompensationThenPlanOnTheFlaggedTurretOnly) {
  ModulationMachine m;
  m.configure(quiet_params());
  const double idle_W = 800.0, cut_W = 1500.0;
  int k = 0;
  for (; k < 500; ++k) {  // idle block: spindle at speed, no cut
    auto in = cutting(idle_W);
    in.idle_block = true;
    in.feed_block = false;
    vibrate(m, k, 0.0);
    m.update(in);
  }
  EXPECT_NEAR(m.output().idle_power_W, idle_W, 1.0);  // compensator 13 (ADC lsb 1 W)
  double path = 0.0;
  for (; k < 2000; ++k) {
    auto in = cutting(idle_W + cut_W);
    in.turret = Turret::Left;
    path += 120.0 / 60.0 * 1e-3;
    in.path_mm[0] = in.path_mm[1] = path;
    vibrate(m, k, k < 1000 ? 0.0 : 20e-6);
    m.update(in);
    if (k == 999) {
      EXPECT_FALSE(m.output().engaged) << "below the dead zone: programmed feeds";
      EXPECT_EQ(m.output().feed_mm_per_min[1], 120.0);
    }
  }
  const auto& o = m.output();
  EXPECT_NEAR(o.cut_power_W, cut_W, 1.0);  // adder 14: N_m − N_idle
  ASSERT_TRUE(o.engaged);
  EXPECT_TRUE(o.reason == Reason::ModulationEngaged || o.reason == Reason::ModulationLimited);
  EXPECT_EQ(o.feed_mm_per_min[0], 120.0) << "the right turret is not flagged: untouched";
  // The planner saw the chain's own readings: a0 the sine's peak, which the ADC truncates to its
  // 1 µm (the sampled peak and the 40 Hz high-pass lose < 0.3 % of 20 µm, so 19 µm), ω_d its
  // frequency (to the detector's resolution 1/(2·gate) = 5 Hz).
  EXPECT_NEAR(o.a0_m, 19e-6, 1e-12);
  EXPECT_NEAR(o.omega_d_rad_per_s / (2.0 * std::numbers::pi), 230.0, 5.0);
  // The plan meets the quenching condition or says it is at its limits, and keeps the programmed
  // feed as the time-mean (the planner's S_min is chosen for it, to the 0.1 mm/min quantum).
  EXPECT_TRUE(o.force_amplitude_planned_N >= o.force_amplitude_required_N * (1.0 - 1e-3) ||
              o.reason == Reason::ModulationLimited);
  EXPECT_NEAR(o.plan.time_mean_feed(), 120.0, 0.5);
  EXPECT_GT(o.plan.s_max_mm_per_min(), 120.0);
  EXPECT_LT(o.plan.s_min_mm_per_min, 120.0);
}

TEST(ModulationMachine, NoIdleReferenceNoPlan) {
  ModulationMachine m;
  m.configure(quiet_params());
  for (int k = 0; k < 1000; ++k) {  // a cut straight away, chatter from the start
    vibrate(m, k, 20e-6);
    m.update(cutting(2300.0));
  }
  EXPECT_FALSE(m.output().engaged);
  EXPECT_EQ(m.output().reason, Reason::ModulationNoIdle);
  EXPECT_FALSE(m.output().idle_known);
  EXPECT_EQ(m.output().feed_mm_per_min[0], 120.0);
  // An idle table is a reference from the start.
  auto p = quiet_params();
  p.power.idle_table_rpm = {100.0, 3000.0};
  p.power.idle_table_W = {800.0, 800.0};
  m.configure(p);
  for (int k = 0; k < 1000; ++k) {
    vibrate(m, k, 20e-6);
    m.update(cutting(2300.0));
  }
  EXPECT_TRUE(m.output().engaged);
  EXPECT_NEAR(m.output().cut_power_W, 1500.0, 1.0);
}

TEST(ModulationMachine, ExternalDetectorsReplaceTheChain) {
  ModulationMachine m;
  auto p = quiet_params();
  p.power.idle_table_rpm = {100.0, 3000.0};
  p.power.idle_table_W = {800.0, 800.0};
  m.configure(p);
  for (int k = 0; k < 200; ++k) {
    auto in = cutting(2300.0);
    in.external_detectors = true;
    in.a0_m = 12e-6;
    in.omega_d_rad_per_s = 1500.0;
    m.update(in);  // no sense(): the chain reads nothing
  }
  EXPECT_TRUE(m.output().engaged);
  EXPECT_EQ(m.output().a0_m, 12e-6);
  EXPECT_EQ(m.output().omega_d_rad_per_s, 1500.0);
}

TEST(ModulationMachine, BadParametersNameThemselves) {
  ModulationMachine m;
  auto name_of = [&](const ModulationMachine::Params& p) -> std::string {
    try {
      m.configure(p);
    } catch (const lathectl::core::ParameterError& e) {
      return e.parameter();
    }
    return "";
  };
  auto p = quiet_params();
  p.module.coefficient = -1.0;
  EXPECT_EQ(name_of(p), "coefficient");
  p = quiet_params();
  p.module.part_mass_kg = 0.0;
  EXPECT_EQ(name_of(p), "part_mass_kg");
  p = quiet_params();
  p.vibration.dead_zone_m = -1.0;
  EXPECT_EQ(name_of(p), "vibration");
  p = quiet_params();
  p.power.idle_table_rpm = {1.0};
  EXPECT_EQ(name_of(p), "power");
  // Before configure(): nothing formed.
  ModulationMachine fresh;
  fresh.update(cutting(1000.0));
  EXPECT_FALSE(fresh.output().engaged);
  EXPECT_EQ(fresh.output().feed_mm_per_min[0], 0.0);
}

// The F conversion: the block's F (G95: mm/rev at the spindle speed; G94: the path velocity in
// mm/s) over the ceiling is the mean feed each turret present keeps; with the factor output
// (LinuxCNC's motion.adaptive-feed) the factor is S/F, 1/ceiling before anything is planned.
TEST(ModulationMachine, TheProgramsFeedOverTheCeiling) {
  ModulationMachine m;
  auto p = quiet_params();
  p.output = ModulationMachine::FeedOutput::Factor;
  p.ceiling = 2.0;
  m.configure(p);
  EXPECT_EQ(m.output().factor, 0.5);
  auto in = cutting(1000.0);
  in.feed_requested = 0.3;  // mm/rev
  in.feed_per_rev = true;
  in.feed_rpm = 800.0;
  in.turrets = 1;  // the right turret alone
  m.update(in);
  EXPECT_DOUBLE_EQ(m.output().mean_feed_mm_per_min, 0.3 * 800.0 / 2.0);
  EXPECT_DOUBLE_EQ(m.output().feed_mm_per_min[0], 120.0);
  EXPECT_EQ(m.output().feed_mm_per_min[1], 0.0) << "no second turret: no feed";
  EXPECT_DOUBLE_EQ(m.output().factor, 0.5) << "S/F with S the mean: 1/ceiling";
  EXPECT_EQ(m.output().feed_ratio, 1.0);
  in.feed_per_rev = false;
  in.feed_requested = 4.0;  // mm/s: 240 mm/min
  m.update(in);
  EXPECT_DOUBLE_EQ(m.output().mean_feed_mm_per_min, 120.0);
  // A ceiling belongs to the factor output, within 1 … 100.
  p.ceiling = 0.5;
  EXPECT_THROW(m.configure(p), lathectl::core::ParameterError);
  p.ceiling = 2.0;
  p.output = ModulationMachine::FeedOutput::Offset;
  EXPECT_THROW(m.configure(p), lathectl::core::ParameterError);
}

// The external offset (Offset): modulating, the flagged axis runs at S/S_p times its planned
// velocity, the offset taking the difference; released in a feed block the offset returns to 0
// at a tenth of the planned speed; out of feed blocks it is 0 at once. The flag moves the
// offset to the other turret's axis only once the offset is 0, asked and applied. The path is
// the flagged axis's travel, planned velocity × S/S_p.
TEST(ModulationMachine, TheExternalOffsetAndTheTurretSwitch) {
  ModulationMachine m;
  auto p = quiet_params();
  p.output = ModulationMachine::FeedOutput::Offset;
  p.power.idle_table_rpm = {100.0, 3000.0};
  p.power.idle_table_W = {800.0, 800.0};
  m.configure(p);
  const double v = 2.0;  // mm/s planned on the right turret's axis (120 mm/min)
  ModulationMachine::Servo sv;
  sv.feed_block = true;
  double planned = 0.0, applied = 0.0, path_expected = 0.0;
  auto period = [&](bool modulated) {
    planned += v * sv.dt_s;
    sv.planned_mm[0] = planned;
    sv.applied_offset_mm[0] = applied;
    const double ratio_before = m.output().feed_ratio;
    m.servo(sv);
    auto in = cutting(2300.0);
    in.external_detectors = true;
    in.a0_m = modulated ? 20e-6 : 0.0;
    in.omega_d_rad_per_s = modulated ? 1400.0 : 0.0;
    in.turret = m.turret();
    in.path_mm[0] = m.path_mm();
    m.update(in);
    applied = m.output().offset_mm;  // motion applies what is asked, a period later
    return ratio_before;
  };
  (void)period(false);  // the first period: no planned velocity yet
  EXPECT_EQ(m.output().axis_vel_mm_per_s, 0.0);
  double off = 0.0;
  for (int k = 0; k < 400; ++k) {
    const double ratio = period(true);
    const bool mod = m.output().engaged && ratio != 1.0;
    EXPECT_NEAR(m.output().axis_vel_mm_per_s, v, 1e-9);
    if (k > 0 && ratio != 1.0) off += (ratio - 1.0) * v * sv.dt_s;
    path_expected += v * (ratio != 1.0 ? ratio : 1.0) * sv.dt_s;
    (void)mod;
  }
  ASSERT_TRUE(m.output().engaged);
  EXPECT_NEAR(m.output().offset_mm, off, 1e-9);
  EXPECT_NE(m.output().offset_mm, 0.0);
  EXPECT_NEAR(m.path_mm(), path_expected, 1e-6);
  // The flag asks for the left turret: held on the right while its offset is not 0.
  sv.turret = Turret::Left;
  sv.on = false;  // the module off: released, the offset returns at 0.1 × |v|
  const double o0 = m.output().offset_mm;
  planned += v * sv.dt_s;
  sv.planned_mm[0] = planned;
  m.servo(sv);
  EXPECT_EQ(m.turret(), Turret::Right);
  EXPECT_NEAR(std::abs(m.output().offset_mm), std::max(0.0, std::abs(o0) - 0.1 * v * sv.dt_s),
              1e-12);
  EXPECT_EQ(m.output().factor, 1.0);
  EXPECT_FALSE(m.output().engaged);
  // Out of feed blocks: 0 at once; the flag moves once the applied offset is 0 too.
  sv.feed_block = false;
  sv.applied_offset_mm[0] = o0;
  m.servo(sv);
  EXPECT_EQ(m.output().offset_mm, 0.0);
  EXPECT_EQ(m.turret(), Turret::Right) << "the axis still applies the offset";
  sv.applied_offset_mm[0] = 0.0;
  m.servo(sv);
  EXPECT_EQ(m.turret(), Turret::Left);
}
