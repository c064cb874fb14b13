// Pulsed flow regulator 5 of seed 000 against formula (1) Q = μπd·h·sqrt(2Δp/ρ)·Δt/T, the
// switching model (dead zone from the overlap) and the obliteration model
// (docs/system-a-pulse-feed.md: the document's advantages 4 and 5).

#include "lathectl/hydraulics/pulse_regulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::hydraulics {
namespace {

SlotOrifice orifice() {
  SlotOrifice o;
  o.spool_diameter_m = 0.008;
  o.discharge_coefficient = 0.65;
  o.pressure_drop_Pa = 0.5e6;
  o.density_kg_per_m3 = 870.0;
  return o;
}

// μπd·sqrt(2Δp/ρ) worked independently: 0.65·π·0.008 = 0.0163363 m;
// sqrt(2·0.5e6/870) = sqrt(1149.43) = 33.9032 m/s → 0.553852 m²/s.
double gain() {
  return 0.65 * std::numbers::pi * 0.008 * std::sqrt(2.0 * 0.5e6 / 870.0);
}

PulseRegulator make(double lap = 0.0, double t_open = 0.0, double t_close = 0.0,
                    ObliterationParams ob = {}) {
  PulseRegulator::Params p;
  p.orifice = orifice();
  p.max_slot_m = 0.2e-3;
  p.lap_m = lap;
  p.opening_time_s = t_open;
  p.closing_time_s = t_close;
  p.obliteration = ob;
  PulseRegulator r;
  r.configure(p);
  return r;
}

// Mean flow over n steps of dt: ∫q dt / (n·dt).
double mean_flow(PulseRegulator& r, double dt, long n, double h, double f, double width) {
  double vol = 0.0;
  for (long k = 0; k < n; ++k) vol += r.step(dt, h, f, width) * dt;
  return vol / (static_cast<double>(n) * dt);
}

TEST(SlotOrifice, GainIsMuPiDSqrt2DpOverRho) {
  EXPECT_NEAR(orifice().gain_per_m(), gain(), 1e-15);
  EXPECT_NEAR(orifice().gain_per_m(), 0.553852, 1e-6);
}

TEST(PulseRegulator, IdealSwitchingMeanFlowEqualsFormula1) {
  const double h = 40e-6, T = 0.05, f = 1.0 / T;
  // Steps: a divisor of the period, two that are not (0.7e-4: 7 periods = 5000 steps;
  // 0.013 s, longer than short pulses: 13 periods = 50 steps), each run over a whole number
  // of periods so that (1) holds exactly, not just on average.
  struct Grid {
    double dt;
    long steps;
  };
  for (const Grid g : {Grid{1e-4, 500L * 70}, Grid{0.7e-4, 5000L * 10}, Grid{0.013, 50L * 20}}) {
    for (const double duty : {0.05, 0.1, 0.25, 0.5, 0.73, 0.9}) {
      auto r = make();
      const double width = duty * T;
      const double q = mean_flow(r, g.dt, g.steps, h, f, width);
      // (1): Q = μπd·h·sqrt(2Δp/ρ)·Δt/T.
      const double q1 = gain() * h * width / T;
      EXPECT_NEAR(q, q1, 1e-9 * q1) << "dt=" << g.dt << " duty=" << duty;
      EXPECT_NEAR(r.ideal_flow(h, f, width), q1, 1e-12 * q1);
    }
  }
  // Worked example: duty 0.2 → Q = 0.553852·40e−6·0.2 = 4.43082e−6 m³/s = 265.85 cm³/min.
  auto r = make();
  EXPECT_NEAR(mean_flow(r, 0.7e-4, 5000, h, f, 0.01) * 6e7, 265.85, 0.01);
}

TEST(PulseRegulator, InstantaneousSpoolFollowsThePulse) {
  auto r = make();
  const double h = 40e-6, f = 20.0, width = 0.01;
  // First 10 ms of the period open: the whole step's flow is K_o·h.
  EXPECT_NEAR(r.step(1e-3, h, f, width), gain() * h, 1e-15);
  EXPECT_DOUBLE_EQ(r.opening_m(), h);
  for (int k = 0; k < 9; ++k) (void)r.step(1e-3, h, f, width);
  // 10 ms later the pulse is over.
  EXPECT_EQ(r.step(1e-3, h, f, width), 0.0);
  EXPECT_EQ(r.opening_m(), 0.0);
}

TEST(PulseRegulator, SymmetricSwitchingRampsCancel) {
  // Opening and closing each take 2 ms for the full 0.2 mm travel (v = 0.1 m/s): a 40 µm slot
  // opens in 0.4 ms and closes in 0.4 ms. The opening ramp loses h²/(2v), the closing ramp gives
  // it back: with no lap the mean flow is still (1).
  const double h = 40e-6, T = 0.05, f = 1.0 / T;
  for (const double duty : {0.1, 0.3, 0.6}) {
    for (const double dt : {1e-4, 0.7e-4}) {
      auto r = make(0.0, 2e-3, 2e-3);
      const long steps = dt == 1e-4 ? 500L * 40 : 5000L * 6;
      const double q = mean_flow(r, dt, steps, h, f, duty * T);
      const double q1 = gain() * h * duty;
      EXPECT_NEAR(q, q1, 1e-6 * q1) << "duty=" << duty << " dt=" << dt;
    }
  }
}

TEST(PulseRegulator, UnequalRampsBendTheFlowByTheClosedForm) {
  // Opening 4 ms, closing 2 ms (full travel 0.2 mm): v_o = 0.05 m/s, v_c = 0.1 m/s.
  // Per pulse: opening ramp loses h²/(2 v_o), closing ramp adds h²/(2 v_c):
  // Q = K_o·f·(h·Δt − h²/(2v_o) + h²/(2v_c)).
  const double h = 40e-6, T = 0.05, f = 20.0, width = 0.01;
  auto r = make(0.0, 4e-3, 2e-3);
  const double q = mean_flow(r, 1e-4, 500L * 40, h, f, width);
  const double vo = 0.2e-3 / 4e-3, vc = 0.2e-3 / 2e-3;
  const double expected = gain() * f * (h * width - h * h / (2 * vo) + h * h / (2 * vc));
  EXPECT_NEAR(q, expected, 1e-9 * expected);
  EXPECT_LT(q, gain() * h * width / T);  // slower opening than closing: below (1)
}

TEST(PulseRegulator, DeadZoneBelowLapOverOpeningSpeed) {
  // Lap 20 µm, full travel lap + max_slot = 220 µm opened in 20 ms: v_open = 0.011 m/s.
  // The spool reaches the slot edge after lap/v_open = 1.818 ms: at f = 20 Hz the dead zone ends
  // at duty = lap/v_open·f = 0.03636.
  const double lap = 20e-6, t_open = 0.02, t_close = 0.02;
  const double h = 40e-6, f = 20.0, T = 1.0 / f;
  const double v_open = (lap + 0.2e-3) / t_open;
  const double v_close = (lap + 0.2e-3) / t_close;
  const double duty0 = lap / v_open * f;
  EXPECT_NEAR(duty0, 0.0363636, 1e-6);

  {
    auto r = make(lap, t_open, t_close);
    for (int k = 0; k < 20 * 500; ++k) ASSERT_EQ(r.step(1e-4, h, f, 0.99 * duty0 * T), 0.0) << k;
    EXPECT_LT(r.spool_position_m(), 0.0);  // never past the lap edge
  }
  {
    auto r = make(lap, t_open, t_close);
    const double width = 1.01 * duty0 * T;
    const double q = mean_flow(r, 1e-4, 20L * 500, h, f, width);
    EXPECT_GT(q, 0.0);
    // Closed form just past the dead zone: the opening grows from 0 at lap/v_open to
    // y_max = v_open·(Δt − lap/v_open) at the end of the pulse, then falls at v_close:
    // area = y_max·(Δt − lap/v_open)/2 + y_max²/(2·v_close) per period.
    const double t_over = width - lap / v_open;
    const double y_max = v_open * t_over;
    const double expected = gain() * f * (0.5 * y_max * t_over + 0.5 * y_max * y_max / v_close);
    EXPECT_NEAR(q, expected, 1e-6 * expected);
    EXPECT_LT(q, 1e-3 * gain() * h * width * f);  // a sliver of the ideal (1)
  }
}

TEST(PulseRegulator, ZeroFrequencyGivesNoFlow) {
  {
    auto r = make();
    for (int k = 0; k < 1000; ++k) ASSERT_EQ(r.step(1e-4, 40e-6, 0.0, 0.01), 0.0);
    EXPECT_EQ(r.opening_m(), 0.0);
  }
  {
    // Pulsing, then f = 0: the spool closes (over its closing time) and the flow stops.
    auto r = make(10e-6, 2e-3, 2e-3);
    (void)mean_flow(r, 1e-4, 30, 40e-6, 20.0, 0.01);  // 3 ms into an open pulse
    EXPECT_GT(r.opening_m(), 0.0);
    (void)mean_flow(r, 1e-4, 30, 40e-6, 0.0, 0.01);  // 3 ms > 2 ms full closing time
    for (int k = 0; k < 1000; ++k) ASSERT_EQ(r.step(1e-4, 40e-6, 0.0, 0.01), 0.0);
    EXPECT_DOUBLE_EQ(r.spool_position_m(), -10e-6);
  }
  {
    // Zero slot stop: no flow whatever the pulses.
    auto r = make();
    for (int k = 0; k < 1000; ++k) ASSERT_EQ(r.step(1e-4, 0.0, 20.0, 0.01), 0.0);
  }
}

TEST(PulseRegulator, DutyOneIsContinuousOpening) {
  auto r = make();
  const double h = 40e-6;
  for (int k = 0; k < 100; ++k) EXPECT_NEAR(r.step(1e-4, h, 20.0, 0.05), gain() * h, 1e-15);
}

TEST(PulseRegulator, SlotStopClampedToMaxSlot) {
  auto r = make();
  // h beyond max_slot (0.2 mm) acts as max_slot.
  EXPECT_NEAR(r.step(1e-4, 1e-3, 20.0, 0.05), gain() * 0.2e-3, 1e-15);
}

TEST(PulseRegulator, ConfigureRejectsBadParameters) {
  PulseRegulator r;
  PulseRegulator::Params p;
  p.orifice = orifice();
  p.max_slot_m = 0.0;
  EXPECT_THROW(r.configure(p), std::invalid_argument);
  p.max_slot_m = 0.2e-3;
  p.lap_m = -1e-6;
  EXPECT_THROW(r.configure(p), std::invalid_argument);
  p.lap_m = 0.0;
  p.opening_time_s = -1.0;
  EXPECT_THROW(r.configure(p), std::invalid_argument);
  p.opening_time_s = 0.0;
  p.orifice.discharge_coefficient = 1.2;
  EXPECT_THROW(r.configure(p), std::invalid_argument);
  p.orifice.discharge_coefficient = 0.65;
  p.orifice.pressure_drop_Pa = 0.0;
  EXPECT_THROW(r.configure(p), std::invalid_argument);
}

// Obliteration: δ(t) = δ_max·(1 − e^(−t/τ)) while the gap stays below the critical gap; the
// effective opening is h − 2δ.
constexpr ObliterationParams kThrottleLayer{0.5e-6, 600.0, 20e-6};

TEST(Obliteration, ThrottleSiltsUpAsOneMinusTwoDeltaOverH) {
  Throttle thr;
  thr.configure({orifice(), kThrottleLayer});
  const double h = 4e-6, dt = 0.1;
  double q = 0.0;
  double t = 0.0;
  for (int k = 0; k < 18000; ++k) {
    q = thr.step(dt, h);
    t += dt;
    if (k == 5999) {  // t = 600 s = τ: δ = 0.5·(1 − e^−1) = 0.31606 µm → 1 − 2δ/h = 0.84197
      const double delta = 0.5e-6 * (1.0 - std::exp(-1.0));
      EXPECT_NEAR(thr.layer_m(), delta, 1e-3 * delta);
      EXPECT_NEAR(q / (gain() * h), 0.84197, 1e-4);
    }
  }
  // t = 1800 s = 3τ: δ = 0.5·(1 − e^−3) = 0.475106 µm; 1 − 2δ/h = 1 − 0.950213/4 = 0.762447.
  const double delta = 0.5e-6 * (1.0 - std::exp(-t / 600.0));
  const double expected = gain() * h * (1.0 - 2.0 * delta / h);
  EXPECT_NEAR(q, expected, 1e-3 * expected);
  EXPECT_NEAR(q / (gain() * h), 0.762447, 1e-3);
  EXPECT_NEAR(thr.layer_m(), 0.475106e-6, 1e-3 * 0.475106e-6);
}

TEST(Obliteration, ThrottleAtOrAboveCriticalGapDoesNotSilt) {
  Throttle thr;
  thr.configure({orifice(), kThrottleLayer});
  const double h = 20e-6;  // = critical gap
  double q = 0.0;
  for (int k = 0; k < 18000; ++k) q = thr.step(0.1, h);
  EXPECT_DOUBLE_EQ(q, gain() * h);
  EXPECT_EQ(thr.layer_m(), 0.0);
}

TEST(Obliteration, ThrottleLayerFlushedByFullOpening) {
  Throttle thr;
  thr.configure({orifice(), kThrottleLayer});
  for (int k = 0; k < 6000; ++k) (void)thr.step(0.1, 4e-6);
  EXPECT_GT(thr.layer_m(), 0.3e-6);
  (void)thr.step(0.1, 50e-6);  // open past the critical gap
  EXPECT_EQ(thr.layer_m(), 0.0);
  EXPECT_NEAR(thr.step(0.1, 4e-6), gain() * 4e-6, 1e-3 * gain() * 4e-6);
}

TEST(Obliteration, PulsedRegulatorKeepsItsFlow) {
  // Same layer model, critical gap 50 µm, slot 40 µm: the slot is below the critical gap and
  // would silt, but every closing stroke sweeps the layer off. Instantaneous switching, so the
  // ideal flow is (1) exactly; between sweeps (one period, 50 ms) the layer can only grow to
  // δ_max·T/τ ≈ 4e−11 m, a relative loss 2δ/h ≤ 2.1e−6.
  const ObliterationParams ob{0.5e-6, 600.0, 50e-6};
  auto r = make(0.0, 0.0, 0.0, ob);
  const double h = 40e-6, f = 20.0, width = 0.01, dt = 1e-3;
  const long per_second = 1000;
  (void)mean_flow(r, dt, per_second, h, f, width);                 // 0–1 s
  const double early = mean_flow(r, dt, per_second, h, f, width);  // 1–2 s
  (void)mean_flow(r, dt, 1797 * per_second, h, f, width);          // 2–1799 s
  const double late = mean_flow(r, dt, per_second, h, f, width);   // 1799–1800 s
  EXPECT_NEAR(late, early, 1e-6 * early);
  const double q1 = gain() * h * width * f;
  EXPECT_NEAR(late, q1, 1e-5 * q1);

  // The continuous throttle at the same 40 µm (below this critical gap) loses
  // 2·0.475 µm / 40 µm = 2.4 % over the same 30 minutes.
  Throttle thr;
  thr.configure({orifice(), ob});
  double q = 0.0;
  for (int k = 0; k < 18000; ++k) q = thr.step(0.1, h);
  EXPECT_NEAR(q / (gain() * h), 1.0 - 2.0 * 0.5e-6 * (1.0 - std::exp(-3.0)) / h, 1e-6);
}

TEST(Obliteration, PartialSweepsSettleAtTheClosedFormBalance) {
  // A closing stroke removes only the share η of the layer, and the layer grows while
  // oil flows through the open slot. Instantaneous switching, pulse Δt = 10 ms every T = 50 ms:
  // each pulse the layer grows by (δ_max − δ)·g, g = 1 − e^(−Δt/τ), and the stroke at its end
  // removes η of it (the flow of the step sees the layer after that pulse's growth). The layer
  // a pulse flows through tends to δ* = δ_max·g/(η + (1 − η)·g):
  //   τ = 10 s (fast, to settle within the test), η = 0.01: g = 1 − e^−0.001 = 9.995002e−4,
  //   δ* = 0.5 µm·9.995002e−4/(0.01 + 0.99·9.995002e−4) = 4.997501e−4/0.010989505 µm
  //      = 0.0454754 µm,  flow q = q₁·(1 − 2δ*/h) = q₁·(1 − 0.00227377) at h = 40 µm.
  const double eta = 0.01, tau = 10.0, T = 0.05, dmax = 0.5e-6, width = 0.01;
  ObliterationParams ob{dmax, tau, 50e-6, eta};
  auto r = make(0.0, 0.0, 0.0, ob);
  const double h = 40e-6, f = 1.0 / T, dt = T / 4.0;
  (void)mean_flow(r, dt, 40000, h, f, width);  // 500 s ≫ the settling, T/(η + g) ≈ 4.5 s
  const double g = 1.0 - std::exp(-width / tau);
  const double d_star = dmax * g / (eta + (1.0 - eta) * g);
  EXPECT_NEAR(d_star, 0.0454754e-6, 1e-12);
  const double q1 = gain() * h * width * f;
  EXPECT_NEAR(mean_flow(r, dt, 400, h, f, width), q1 * (1.0 - 2.0 * d_star / h), 1e-9 * q1);
  // A finer step (8 steps a pulse) sees the layer grow within the pulse: the same balance, the
  // flow between the layer after the stroke, (1 − η)·δ*, and the one before it, δ*.
  auto r2 = make(0.0, 0.0, 0.0, ob);
  (void)mean_flow(r2, T / 40.0, 400000, h, f, width);
  const double q_fine = mean_flow(r2, T / 40.0, 4000, h, f, width);
  EXPECT_GE(q_fine, q1 * (1.0 - 2.0 * d_star / h) - 1e-12 * q1);
  EXPECT_LE(q_fine, q1 * (1.0 - 2.0 * (1.0 - eta) * d_star / h) + 1e-12 * q1);
  // η = 0: no stroke helps; the slot silts toward h − 2δ_max like a throttle (over its open time).
  ObliterationParams none{dmax, tau, 50e-6, 0.0};
  auto r0 = make(0.0, 0.0, 0.0, none);
  (void)mean_flow(r0, dt, 40000, h, f, width);  // 100 s open = 10 τ
  EXPECT_NEAR(mean_flow(r0, dt, 400, h, f, width), q1 * (1.0 - 2.0 * dmax / h), 1e-4 * q1);
  PulseRegulator::Params bad;
  bad.obliteration.removal_per_stroke = 1.5;
  PulseRegulator rb;
  EXPECT_THROW(rb.configure(bad), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::hydraulics
