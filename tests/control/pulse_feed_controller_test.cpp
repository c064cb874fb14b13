// Feed controller of the pulsed hydraulic slide (seed 000) against the seed's correction laws:
//   AIM (2): Ka = μπd·sqrt(2Δp/ρ)·Δt·f,   (4): Δh = K_leak·ΔPy/(Ka·F)
//   FIM (6): Kf = μπd·sqrt(2Δp/ρ)·h·Δt,   Δf = K_leak·ΔPy/(Kf·F)
// plus the roughing PI (limits, anti-windup) and the sensor-fault behaviour described in
// include/lathectl/control/pulse_feed_controller.hpp.

#include "lathectl/control/pulse_feed_controller.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace lathectl::control {
namespace {

using Ctl = PulseFeedController;

// Regulator of examples/scenarios/a_finishing_aim.toml: d = 5 mm, Δp = 0.2 MPa, ρ = 870, μ = 0.65:
// μπd·sqrt(2Δp/ρ) = 0.0102102·21.4423 = 0.218929 m²/s.
const double kGain = 0.65 * std::numbers::pi * 0.005 * std::sqrt(2.0 * 0.2e6 / 870.0);
constexpr double kF = 8e-4;                   // 8 cm²
constexpr double kLeak = 50e-6 / 60.0 / 1e6;  // 50 cm³/min/MPa = 8.3333e−13 m³/(s·Pa)
constexpr double kFriction = 50.0;            // N
constexpr double kFeed = 1e-3;                // 60 mm/min
constexpr double kVperN = 5e-3;               // 0.1 V/µm / 20 N/µm
constexpr double kOffset = 0.5;               // V

Ctl::Params params(Ctl::Modulation m = Ctl::Modulation::Amplitude,
                   Ctl::Mode mode = Ctl::Mode::Finishing) {
  Ctl::Params p;
  p.modulation = m;
  p.mode = mode;
  p.period_s = 1e-3;
  p.regulator_gain_per_m = kGain;
  p.pulse_width_s = 0.005;
  p.frequency_Hz = 20.0;
  p.slot_m = 40e-6;
  p.piston_area_m2 = kF;
  p.leak_m3_per_s_Pa = kLeak;
  p.friction_N = kFriction;
  p.compliance_m3_per_Pa = 0.0;  // the seed's law
  p.feed_m_per_s = kFeed;
  p.force_set_N = 200.0;
  p.sensor_V_per_N = kVperN;
  p.sensor_offset_V = kOffset;
  p.force_filter_s = 0.0;
  p.sensor_monitor = {-0.5, 10.5, 0.0, 0.0};
  p.slot_min_m = 0.0;
  p.slot_max_m = 1e-4;
  p.frequency_min_Hz = 0.0;
  p.frequency_max_Hz = 50.0;
  p.duty_max = 0.9;
  p.frequency_ramp_Hz_per_s = 1e6;
  p.kp = 3.0;
  p.ti_s = 0.5;
  p.feed_min_fraction = 0.05;
  return p;
}

Ctl make(const Ctl::Params& p, double start_force = 100.0) {
  Ctl c;
  c.configure(p);
  c.start(start_force);
  return c;
}

Ctl::Input at_force(double P) {
  return {kOffset + kVperN * P};
}

// Runs n updates at force P; out is the last one's.
void run(Ctl& c, double P, int n, Ctl::Output& out) {
  for (int k = 0; k < n; ++k) c.update(at_force(P), out);
}

TEST(PulseFeedController, GainsAreSeedFormulas2And6) {
  const auto aim = make(params(Ctl::Modulation::Amplitude));
  // (2): Ka = 0.218929·0.005·20 = 0.0218929 m²/s.
  EXPECT_NEAR(aim.ka(), kGain * 0.005 * 20.0, 1e-15);
  EXPECT_NEAR(aim.ka(), 0.0218929, 1e-7);
  const auto fim = make(params(Ctl::Modulation::Frequency));
  // (6): Kf = 0.218929·40e−6·0.005 = 4.37858e−8 m³.
  EXPECT_NEAR(fim.kf(), kGain * 40e-6 * 0.005, 1e-20);
  EXPECT_NEAR(fim.kf(), 4.37858e-8, 1e-12);
}

TEST(PulseFeedController, FinishingAimSlotIsH0PlusSeedFormula4) {
  auto c = make(params());
  const double Ka = kGain * 0.005 * 20.0;
  Ctl::Output out;
  const double P0 = 100.0;
  run(c, P0, 5, out);
  ASSERT_EQ(out.reason, Reason::None);
  // h0 from (3) solved for the slot: (S·F + K·(P0 + F_fr)/F)/Ka
  //    = (1e−3·8e−4 + 8.3333e−13·150/8e−4)/0.021893 = (8e−7 + 1.5625e−7)/0.021893 = 43.678 µm.
  const double h0 = (kFeed * kF + kLeak * (P0 + kFriction) / kF) / Ka;
  EXPECT_NEAR(out.slot_m, h0, 1e-12 * h0);
  EXPECT_NEAR(out.slot_m, 43.678e-6, 1e-9);
  EXPECT_DOUBLE_EQ(out.frequency_Hz, 20.0);  // AIM: frequency fixed
  EXPECT_DOUBLE_EQ(out.feed_cmd_m_per_s, kFeed);
  EXPECT_NEAR(out.force_estimate_N, P0, 1e-9);
  EXPECT_EQ(out.reason, Reason::None);
  EXPECT_FALSE(out.alarm);

  for (const double dP : {50.0, 100.0, 400.0, -60.0}) {
    run(c, P0 + dP, 3, out);
    ASSERT_EQ(out.reason, Reason::None);
    // (4): Δh = K_leak·ΔPy/(Ka·F); ΔPy = 100 N → 8.3333e−11/(0.021893·8e−4) = 4.7580 µm.
    const double dh = kLeak * dP / (Ka * kF);
    EXPECT_NEAR(out.slot_m - h0, dh, 1e-9 * h0) << "dP=" << dP;
    if (dP == 100.0) {
      EXPECT_NEAR(out.slot_m - h0, 4.7580e-6, 1e-9);
    }
    // And (4) restores (5): the slot's extra flow Ka·Δh/F cancels the extra leakage K·ΔP/F².
    EXPECT_NEAR(Ka * (out.slot_m - h0) / kF, kLeak * dP / (kF * kF), 1e-9 * kFeed);
  }
}

TEST(PulseFeedController, FinishingAimAfterForceFilterSettles) {
  auto p = params();
  p.force_filter_s = 0.02;  // 20 ms low-pass on the estimate
  auto c = make(p, 100.0);
  const double Ka = c.ka();
  const double h0 = (kFeed * kF + kLeak * (100.0 + kFriction) / kF) / Ka;
  Ctl::Output out;
  run(c, 300.0, 1, out);
  // One period into a 20 ms filter only 1 − e^(−1/20) = 4.9 % of the step is seen.
  EXPECT_NEAR(out.force_estimate_N, 100.0 + 200.0 * (1.0 - std::exp(-0.05)), 1e-9);
  run(c, 300.0, 399, out);  // 0.4 s = 20 τ: settled to e^−20
  EXPECT_NEAR(out.force_estimate_N, 300.0, 1e-6);
  EXPECT_NEAR(out.slot_m - h0, kLeak * 200.0 / (Ka * kF), 1e-6 * h0);
}

TEST(PulseFeedController, FinishingAddsCompressedOilDuringAForceRamp) {
  // Beyond the seed: while the force rises at dP/dt the controller adds C·(dP/dt)/F to the flow.
  auto p = params();
  p.compliance_m3_per_Pa = 5e-13;
  p.rate_filter_s = 0.0;
  auto c = make(p, 100.0);
  const double Ka = c.ka();
  Ctl::Output out;
  double P = 100.0;
  for (int k = 0; k < 50; ++k) {
    P += 1.0;  // 1 N per 1 ms period = 1000 N/s
    c.update(at_force(P), out);
  }
  const double h_static = (kFeed * kF + kLeak * (P + kFriction) / kF) / Ka;
  // Extra: 5e−13·1000/8e−4 = 6.25e−7 m³/s → 6.25e−7/0.021893 = 28.548 µm of slot.
  const double extra = 5e-13 * 1000.0 / kF / Ka;
  EXPECT_NEAR(out.slot_m, h_static + extra, 1e-6 * h_static);
  EXPECT_NEAR(extra, 28.548e-6, 1e-9);
  run(c, P, 3, out);  // ramp over: the term vanishes
  EXPECT_NEAR(out.slot_m, h_static, 1e-9 * h_static);
}

TEST(PulseFeedController, FinishingAimSaturatesAtSlotMax) {
  auto c = make(params());
  Ctl::Output out;
  // 1500 N (sensor 8 V, in range): the slot would need (8e−7 + K·1550/F)/Ka = 110 µm > 100 µm.
  run(c, 1500.0, 2, out);
  EXPECT_DOUBLE_EQ(out.slot_m, 1e-4);
  EXPECT_EQ(out.reason, Reason::OutputHigh);
}

TEST(PulseFeedController, FinishingFimFrequencyChangeIsKleakDpOverKfF) {
  auto c = make(params(Ctl::Modulation::Frequency), 100.0);
  const double Kf = kGain * 40e-6 * 0.005;
  Ctl::Output out;
  run(c, 100.0, 3, out);
  ASSERT_EQ(out.reason, Reason::None);
  // f0 = (S·F + K·(P0 + F_fr)/F)/Kf = 9.5625e−7/4.3786e−8 = 21.839 Hz.
  const double f0 = (kFeed * kF + kLeak * 150.0 / kF) / Kf;
  EXPECT_NEAR(out.frequency_Hz, f0, 1e-9 * f0);
  EXPECT_NEAR(out.frequency_Hz, 21.839, 1e-3);
  EXPECT_DOUBLE_EQ(out.slot_m, 40e-6);  // FIM: slot fixed
  for (const double dP : {100.0, 250.0, -40.0}) {
    run(c, 100.0 + dP, 3, out);
    ASSERT_EQ(out.reason, Reason::None);
    // Δf = K_leak·ΔPy/(Kf·F); ΔPy = 100 N → 8.3333e−11/(4.3786e−8·8e−4) = 2.3790 Hz.
    EXPECT_NEAR(out.frequency_Hz - f0, kLeak * dP / (Kf * kF), 1e-9 * f0) << "dP=" << dP;
    if (dP == 100.0) {
      EXPECT_NEAR(out.frequency_Hz - f0, 2.3790, 1e-4);
    }
  }
}

TEST(PulseFeedController, FimRespectsConverterRamp) {
  auto p = params(Ctl::Modulation::Frequency);
  p.frequency_ramp_Hz_per_s = 200.0;  // 0.2 Hz per 1 ms period
  auto c = make(p, 100.0);
  const double Kf = c.kf();
  Ctl::Output out;
  run(c, 100.0, 2, out);
  const double f0 = out.frequency_Hz;
  const double target = f0 + kLeak * 300.0 / (Kf * kF);  // ΔP = 300 N → Δf = 7.137 Hz
  double prev = f0;
  int limited = 0;
  for (int k = 0; k < 100; ++k) {
    c.update(at_force(400.0), out);
    ASSERT_LE(std::abs(out.frequency_Hz - prev), 200.0 * 1e-3 + 1e-12) << k;
    ASSERT_LE(out.frequency_Hz, target + 1e-9);
    if (out.reason != Reason::None) {
      EXPECT_EQ(out.reason, Reason::RateLimited);
      ++limited;
    }
    prev = out.frequency_Hz;
  }
  // 7.137 Hz at 0.2 Hz per period: 35 rate-limited periods, then on target.
  EXPECT_EQ(limited, static_cast<int>(std::floor((target - f0) / 0.2)));
  EXPECT_NEAR(out.frequency_Hz, target, 1e-9 * target);
  EXPECT_EQ(out.reason, Reason::None);
}

TEST(PulseFeedController, FimFrequencyCappedByDutyMax) {
  auto p = params(Ctl::Modulation::Frequency);
  p.duty_max = 0.1;  // f·Δt ≤ 0.1 → f ≤ 20 Hz < frequency_max 50 Hz
  auto c = make(p, 100.0);
  Ctl::Output out;
  run(c, 2000.0, 3, out);
  EXPECT_NEAR(out.frequency_Hz, 20.0, 1e-12);
  EXPECT_EQ(out.reason, Reason::OutputHigh);
}

TEST(PulseFeedController, RoughingBelowSetHoldsProgrammedFeed) {
  auto c = make(params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing), 100.0);
  Ctl::Output out;
  for (int k = 0; k < 200; ++k) {
    c.update(at_force(150.0), out);
    ASSERT_DOUBLE_EQ(out.feed_cmd_m_per_s, kFeed);  // u clamped at 1: never above programmed
    ASSERT_EQ(out.reason, Reason::OutputHigh);
  }
  // Slot for the programmed feed at the measured force, (3) solved for h.
  EXPECT_NEAR(out.slot_m, (kFeed * kF + kLeak * (150.0 + kFriction) / kF) / c.ka(), 1e-15);
}

TEST(PulseFeedController, RoughingAboveSetReducesFeedByPiLaw) {
  auto p = params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing);
  p.kp = 0.2;
  p.ti_s = 0.5;
  auto c = make(p, 200.0);
  Ctl::Output out;
  double prev = kFeed;
  // Force 300 N against 200 N set: e = (200 − 300)/200 = −0.5.
  for (int k = 1; k <= 100; ++k) {
    c.update(at_force(300.0), out);
    ASSERT_LT(out.feed_cmd_m_per_s, prev) << k;
    ASSERT_LE(out.feed_cmd_m_per_s, kFeed);
    prev = out.feed_cmd_m_per_s;
  }
  // PI from the bumpless start u = 1: u = 1 + kp·e + (kp/ti)·e·t = 1 − 0.1 − 0.4·0.5·0.1 = 0.88.
  EXPECT_NEAR(out.feed_cmd_m_per_s, 0.88 * kFeed, 1e-9 * kFeed);
  EXPECT_NEAR(out.slot_m, (0.88 * kFeed * kF + kLeak * (300.0 + kFriction) / kF) / c.ka(), 1e-12);
  // Held long enough, it stops at the minimum fraction.
  run(c, 300.0, 20000, out);
  EXPECT_NEAR(out.feed_cmd_m_per_s, 0.05 * kFeed, 1e-15);
  EXPECT_EQ(out.reason, Reason::OutputLow);
}

TEST(PulseFeedController, RoughingFimReducesFrequency) {
  auto c = make(params(Ctl::Modulation::Frequency, Ctl::Mode::Roughing), 150.0);
  Ctl::Output out;
  run(c, 150.0, 10, out);
  const double f_before = out.frequency_Hz;
  run(c, 300.0, 10, out);
  EXPECT_LT(out.feed_cmd_m_per_s, kFeed);
  EXPECT_LT(out.frequency_Hz, f_before);
  EXPECT_NEAR(out.frequency_Hz,
              (out.feed_cmd_m_per_s * kF + kLeak * (300.0 + kFriction) / kF) / c.kf(), 1e-9);
}

TEST(PulseFeedController, AntiWindupLeavesLimitOnNextUpdate) {
  auto c = make(params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing), 50.0);
  Ctl::Output out;
  // 20 s saturated at the programmed feed with the force far below the set (e = +0.75).
  run(c, 50.0, 20000, out);
  EXPECT_DOUBLE_EQ(out.feed_cmd_m_per_s, kFeed);
  EXPECT_EQ(out.reason, Reason::OutputHigh);
  // Force rises above the set: a wound-up integrator (0.75·20 s·kp/ti = 90) would keep the feed at
  // the limit for seconds; here the very next update leaves it.
  c.update(at_force(220.0), out);
  EXPECT_LT(out.feed_cmd_m_per_s, kFeed);
  EXPECT_NE(out.reason, Reason::OutputHigh);
}

// Regression (found by this test, fixed): The PiRegulator comment promises that the
// saturated output "leaves the limit as soon as the error changes sign". Back-calculation stores
// integral = out_max − kp·e (clamped at out_min), so after saturation at a large positive error
// the output falls below the limit as soon as the error *decreases*, even while it stays
// positive: after 20 s at e = 0.75 the integrator sits at out_min = 0.05, and a force rising to
// 90 % of the set (e = +0.1) gives u = 0.05 + 3·0.1 = 0.35 — the feed drops to 35 % although the
// force is below its set value (e.g. entering the cut from an air cut).
TEST(PulseFeedController, AntiWindupHoldsLimitWhileErrorStaysPositive) {
  auto c = make(params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing), 50.0);
  Ctl::Output out;
  run(c, 50.0, 20000, out);
  c.update(at_force(180.0), out);  // still below the 200 N set
  EXPECT_DOUBLE_EQ(out.feed_cmd_m_per_s, kFeed);
}

// Regression (found by this test, fixed): a default-constructed controller (no configure())
// divided by Ka = 0 and answered OutputHigh with the slot at its default maximum (0.2 mm), i.e.
// the valve fully open — the unsafe direction for a real machine. Now the valve stays shut.
TEST(PulseFeedController, UpdateBeforeConfigureKeepsTheValveShut) {
  Ctl c;
  Ctl::Output out;
  out.slot_m = out.frequency_Hz = out.feed_cmd_m_per_s = 1.0;
  c.update(at_force(100.0), out);
  EXPECT_EQ(out.slot_m, 0.0);
  EXPECT_EQ(out.frequency_Hz, 0.0);
  EXPECT_EQ(out.feed_cmd_m_per_s, 0.0);
  EXPECT_EQ(out.reason, Reason::None);
}

TEST(PulseFeedController, SensorNotFiniteStopsRoughingFeed) {
  for (const auto m : {Ctl::Modulation::Amplitude, Ctl::Modulation::Frequency}) {
    auto c = make(params(m, Ctl::Mode::Roughing), 150.0);
    Ctl::Output out;
    run(c, 150.0, 10, out);
    EXPECT_FALSE(out.alarm);
    for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
      auto c2 = make(params(m, Ctl::Mode::Roughing), 150.0);
      run(c2, 150.0, 10, out);
      c2.update({bad}, out);
      EXPECT_TRUE(out.alarm);
      EXPECT_EQ(out.alarm_reason, Reason::SensorNotFinite);
      EXPECT_EQ(out.reason, Reason::SensorNotFinite);
      EXPECT_EQ(out.feed_cmd_m_per_s, 0.0);
      if (m == Ctl::Modulation::Amplitude) {
        EXPECT_EQ(out.slot_m, 0.0);
      } else {
        EXPECT_EQ(out.frequency_Hz, 0.0);
      }
    }
  }
}

TEST(PulseFeedController, FinishingFaultFreezesLastOutputAndLatches) {
  for (const auto m : {Ctl::Modulation::Amplitude, Ctl::Modulation::Frequency}) {
    auto c = make(params(m, Ctl::Mode::Finishing), 100.0);
    Ctl::Output out;
    run(c, 180.0, 10, out);
    const Ctl::Output good = out;
    c.update({std::nan("")}, out);
    EXPECT_TRUE(out.alarm);
    EXPECT_EQ(out.alarm_reason, Reason::SensorNotFinite);
    EXPECT_EQ(out.slot_m, good.slot_m);
    EXPECT_EQ(out.frequency_Hz, good.frequency_Hz);
    EXPECT_EQ(out.feed_cmd_m_per_s, good.feed_cmd_m_per_s);
    // Latched: a valid sample at another force does not release it or move the output.
    c.update(at_force(400.0), out);
    EXPECT_TRUE(out.alarm);
    EXPECT_EQ(out.slot_m, good.slot_m);
    EXPECT_EQ(out.frequency_Hz, good.frequency_Hz);
    // reset_alarm() clears it; the next valid sample is used again.
    c.reset_alarm();
    c.update(at_force(400.0), out);
    EXPECT_EQ(out.reason, Reason::None);
    EXPECT_FALSE(out.alarm);
    EXPECT_EQ(out.alarm_reason, Reason::None);
    if (m == Ctl::Modulation::Amplitude) {
      EXPECT_GT(out.slot_m, good.slot_m);
    } else {
      EXPECT_GT(out.frequency_Hz, good.frequency_Hz);
    }
  }
}

TEST(PulseFeedController, StuckSensorDetectedAfterStuckTime) {
  auto p = params();
  p.sensor_monitor.stuck_time_s = 0.05;  // 50 periods of 1 ms
  p.sensor_monitor.stuck_tolerance = 0.0;
  auto c = make(p, 100.0);
  Ctl::Output out;
  // A live, noisy signal never repeats: no alarm over 1 s.
  for (int k = 0; k < 1000; ++k) {
    c.update(at_force(100.0 + ((k % 2) ? 0.3 : -0.3)), out);
    ASSERT_EQ(out.reason, Reason::None) << k;
  }
  // Frozen at one value: the first sample starts the clock; 49 further periods (49 ms) are
  // below the 50 ms stuck time, so no alarm yet.
  int first_alarm = -1;
  for (int k = 0; k < 100; ++k) {
    c.update(at_force(123.0), out);
    if (out.alarm && first_alarm < 0) first_alarm = k;
  }
  ASSERT_GE(first_alarm, 0);
  EXPECT_GE(first_alarm, 49);
  EXPECT_LE(first_alarm, 52);
  EXPECT_TRUE(out.alarm);
  EXPECT_EQ(out.alarm_reason, Reason::SensorStuck);
}

TEST(PulseFeedController, StuckToleranceCountsSmallChangesAsUnchanged) {
  auto p = params();
  p.sensor_monitor.stuck_time_s = 0.05;
  p.sensor_monitor.stuck_tolerance = 1e-3;  // V
  auto c = make(p, 100.0);
  Ctl::Output out;
  for (int k = 0; k < 100; ++k)
    c.update({kOffset + kVperN * 100.0 + ((k % 2) ? 2e-4 : -2e-4)}, out);
  EXPECT_TRUE(out.alarm);
  EXPECT_EQ(out.alarm_reason, Reason::SensorStuck);
}

TEST(PulseFeedController, OutOfRangeSensorAlarms) {
  for (const double v : {11.0, -1.0}) {  // valid range [−0.5, 10.5] V
    auto c = make(params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing), 100.0);
    Ctl::Output out;
    run(c, 100.0, 5, out);
    c.update({v}, out);
    EXPECT_TRUE(out.alarm);
    EXPECT_EQ(out.alarm_reason, Reason::SensorOutOfRange);
    EXPECT_EQ(out.slot_m, 0.0);
    c.reset_alarm();
    c.update(at_force(100.0), out);
    EXPECT_FALSE(out.alarm);
  }
}

TEST(PulseFeedController, ConfigureRejectsBadParameters) {
  auto bad = [](auto edit) {
    auto p = params();
    edit(p);
    Ctl c;
    EXPECT_THROW(c.configure(p), std::invalid_argument);
  };
  bad([](Ctl::Params& p) { p.feed_m_per_s = 0.0; });
  bad([](Ctl::Params& p) { p.period_s = 0.0; });
  bad([](Ctl::Params& p) { p.regulator_gain_per_m = 0.0; });
  bad([](Ctl::Params& p) { p.pulse_width_s = 0.0; });
  bad([](Ctl::Params& p) { p.piston_area_m2 = -1.0; });
  bad([](Ctl::Params& p) { p.leak_m3_per_s_Pa = -1e-13; });
  bad([](Ctl::Params& p) { p.sensor_V_per_N = 0.0; });
  bad([](Ctl::Params& p) { p.frequency_Hz = 300.0; });  // f·Δt = 1.5 > 1
  bad([](Ctl::Params& p) { p.slot_max_m = 0.0; });      // ≤ slot_min
  bad([](Ctl::Params& p) { p.duty_max = 0.0; });
  bad([](Ctl::Params& p) { p.duty_max = 1.5; });
  bad([](Ctl::Params& p) { p.feed_min_fraction = 1.0; });
  bad([](Ctl::Params& p) { p.sensor_monitor.min = 20.0; });  // min ≥ max
  bad([](Ctl::Params& p) {
    p.mode = Ctl::Mode::Roughing;
    p.force_set_N = 0.0;
  });
  bad([](Ctl::Params& p) {
    p.modulation = Ctl::Modulation::Frequency;
    p.slot_m = 0.0;
  });
  bad([](Ctl::Params& p) {
    p.modulation = Ctl::Modulation::Frequency;
    p.frequency_ramp_Hz_per_s = 0.0;
  });
  bad([](Ctl::Params& p) {
    p.modulation = Ctl::Modulation::Frequency;
    p.frequency_max_Hz = 0.0;
  });
  Ctl c;
  EXPECT_NO_THROW(c.configure(params()));
}

TEST(PulseFeedController, ActuatorForInvertsSeedFormula3) {
  const auto c = make(params());
  // The slot that gives feed S at load P: plugging it back into (2) and (3) returns S.
  for (const double P : {0.0, 100.0, 1000.0}) {
    const double h = c.actuator_for(kFeed, P);
    const double S = c.ka() * h / kF - kLeak * (P + kFriction) / (kF * kF);
    EXPECT_NEAR(S, kFeed, 1e-15);
  }
}

// A frozen reading never drives the feed up (issue "Results a user can trust", finding 2). In
// roughing with a filtered force estimate, a reading frozen above the set force but below the
// estimate lets the estimate fall toward it and the PI's P term rise: before the fix the slot
// opened for the 50 ms until the stuck alarm. Now, from the third equal sample on (suspect: two
// unchanged comparisons, the rule for tolerance 0), the slot only holds or closes, on every
// sample, and the alarm still latches at the stuck time.
TEST(PulseFeedController, FrozenReadingNeverOpensTheSlot) {
  auto p = params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing);
  p.force_filter_s = 0.02;
  p.sensor_monitor.stuck_time_s = 0.05;
  p.sensor_monitor.stuck_tolerance = 0.0;
  auto c = make(p, 200.0);
  Ctl::Output out;
  // A live, noisy overload: 230 N ± 0.3 N for 0.2 s — the PI closes the slot part-way
  // (u = 1 − 6·0.15·0.2 − 3·0.15 ≈ 0.37, off its 0.05 floor).
  for (int k = 0; k < 200; ++k) {
    c.update(at_force(230.0 + ((k % 2) ? 0.3 : -0.3)), out);
    ASSERT_EQ(out.reason, Reason::None) << k;
  }
  // The sensor freezes at 210 N (still above the 200 N set force): the filtered estimate falls
  // toward it and the P term rises by 3·0.1 over ~20 ms.
  double last_slot = out.slot_m;
  int alarm_at = -1, suspect = 0;
  for (int k = 0; k < 100; ++k) {
    c.update(at_force(210.0), out);
    if (k >= 2) {
      ASSERT_LE(out.slot_m, last_slot) << "frozen sample " << k;
    }
    if (out.reason == Reason::SensorSuspect) ++suspect;
    if (out.alarm && alarm_at < 0) alarm_at = k;
    last_slot = out.slot_m;
  }
  EXPECT_GT(suspect, 10);
  EXPECT_GE(alarm_at, 49);
  EXPECT_LE(alarm_at, 52);
  EXPECT_EQ(out.alarm_reason, Reason::SensorStuck);
}

// A live sensor is not affected: noise that never repeats exactly gives no suspect state, and
// the slot opens again as the force falls below the set value.
TEST(PulseFeedController, LiveNoisySensorIsNeverSuspect) {
  auto p = params(Ctl::Modulation::Amplitude, Ctl::Mode::Roughing);
  p.force_filter_s = 0.02;
  p.sensor_monitor.stuck_time_s = 0.05;
  auto c = make(p, 200.0);
  Ctl::Output out;
  for (int k = 0; k < 200; ++k) c.update(at_force(300.0 + ((k % 2) ? 0.3 : -0.3)), out);
  const double closed = out.slot_m;
  for (int k = 0; k < 500; ++k) {
    c.update(at_force(150.0 + 0.3 * std::sin(0.7 * k)), out);
    ASSERT_NE(out.reason, Reason::SensorSuspect) << k;
  }
  EXPECT_GT(out.slot_m, closed);
}

// The suspect count follows the sensor's scale: P(|Δ| ≤ tol) = erf(tol/(2σ)) = p, N the least
// count with p^N ≤ 1e-6 (≥ 2, ≤ the stuck time's count).
TEST(SignalMonitor, SuspectCountFromNoiseAndTolerance) {
  SignalMonitor::Params m;
  m.stuck_time_s = 0.05;
  m.period_s = 1e-3;
  EXPECT_EQ(SignalMonitor::suspect_samples_for(m), 2);  // tol 0: an exact repeat
  m.noise_sigma = 5e-3;
  m.stuck_tolerance = 1e-3;  // p = erf(0.1) = 0.11246: N = ceil(ln 1e-6 / ln p) = ceil(6.317) = 7
  EXPECT_EQ(SignalMonitor::suspect_samples_for(m), 7);
  m.stuck_tolerance = 0.1;  // p = erf(10) ≈ 1: capped at the stuck count, 50
  EXPECT_EQ(SignalMonitor::suspect_samples_for(m), 50);
  m.stuck_time_s = 0.0;  // check off
  EXPECT_EQ(SignalMonitor::suspect_samples_for(m), 0);
}

}  // namespace
}  // namespace lathectl::control
