// Hydraulic feed slide (include/lathectl/hydraulics/feed_slide.hpp) against seed 000, formula
// (3): in steady motion S = Q/F − K_leak·P/F², with P the whole load on the piston (cutting load
// plus Coulomb friction, plus b·S for viscous friction); and against the linearised hydraulic
// natural frequency ω_h = F·sqrt(B/(V·m)).

#include "lathectl/hydraulics/feed_slide.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace lathectl::hydraulics {
namespace {

// F = 20 cm², V0 = 100 cm³, B = 1.4 GPa, K_leak = 200 cm³/min/MPa = 200e−6/60/1e6 = 3.3333e−12
// m³/(s·Pa), m = 50 kg, F_c = 200 N.
FeedSlide::Params base_params() {
  FeedSlide::Params p;
  p.piston_area_m2 = 20e-4;
  p.dead_volume_m3 = 100e-6;
  p.bulk_modulus_Pa = 1.4e9;
  p.leak_m3_per_s_Pa = 200e-6 / 60.0 / 1e6;
  p.mass_kg = 50.0;
  p.coulomb_friction_N = 200.0;
  p.viscous_friction_N_s_per_m = 0.0;
  return p;
}

FeedSlide make(const FeedSlide::Params& p) {
  FeedSlide s;
  s.configure(p);
  return s;
}

// Runs for `seconds` at constant Q and P; returns the mean velocity over the last 0.1 s.
double settle(FeedSlide& s, double q, double load, double seconds, double dt = 1e-4) {
  const long n = std::lround(seconds / dt);
  const long tail = std::lround(0.1 / dt);
  double acc = 0.0;
  for (long k = 0; k < n; ++k) {
    s.step(dt, q, load);
    if (k >= n - tail) acc += s.state().v_m_per_s;
  }
  return acc / static_cast<double>(tail);
}

TEST(FeedSlide, SteadyVelocityIsSeedFormula3) {
  const auto p = base_params();
  const double F = p.piston_area_m2, K = p.leak_m3_per_s_Pa;
  const double P = 1000.0, Q = 6e-6;
  // (3) with P + F_c: S = 6e−6/20e−4 − 3.3333e−12·1200/(20e−4)² = 3.0e−3 − 1.0e−3 = 2.0e−3 m/s.
  const double S = Q / F - K * (P + p.coulomb_friction_N) / (F * F);
  EXPECT_NEAR(S, 2.0e-3, 1e-12);
  auto s = make(p);
  s.set_steady(0.0, P);  // at rest, pressure balancing the load
  const double v = settle(s, Q, P, 4.0);
  EXPECT_NEAR(v, S, 1e-4 * S);
  EXPECT_NEAR(s.state().v_m_per_s, S, 1e-4 * S);
  // Steady pressure carries the load plus friction; the leakage is K·p.
  EXPECT_NEAR(s.state().p_cyl_Pa, (P + p.coulomb_friction_N) / F, 1e-4 * (P + 200.0) / F);
  EXPECT_NEAR(s.leak_flow(), K * (P + p.coulomb_friction_N) / F, 1e-4 * K * 1200.0 / F);
}

TEST(FeedSlide, SteadyVelocityIsSeedFormula3WithDamper) {
  auto p = base_params();
  // Damper: C_d = 0.5 cm³/MPa = 5e−13 m³/Pa, R_d = 0.06 MPa·s/cm³ = 6e10 Pa·s/m³ (τ = 30 ms).
  p.damper_capacitance_m3_per_Pa = 0.5e-6 / 1e6;
  p.damper_resistance_Pa_s_per_m3 = 0.06e6 / 1e-6;
  const double F = p.piston_area_m2, K = p.leak_m3_per_s_Pa;
  for (const double P : {500.0, 1000.0, 3000.0}) {
    const double Q = 6e-6;
    const double S = Q / F - K * (P + p.coulomb_friction_N) / (F * F);
    auto s = make(p);
    s.set_steady(0.0, P);
    const double v = settle(s, Q, P, 4.0);
    EXPECT_NEAR(v, S, 1e-4 * S) << "P=" << P;
    // In steady flow the damper passes Q through R_d: p_d − p_c = R_d·Q.
    EXPECT_NEAR(s.state().p_damper_Pa - s.state().p_cyl_Pa, p.damper_resistance_Pa_s_per_m3 * Q,
                1e-3 * p.damper_resistance_Pa_s_per_m3 * Q);
  }
}

TEST(FeedSlide, SteadyVelocityWithViscousFriction) {
  auto p = base_params();
  p.viscous_friction_N_s_per_m = 50000.0;
  const double F = p.piston_area_m2, K = p.leak_m3_per_s_Pa, b = p.viscous_friction_N_s_per_m;
  const double P = 1000.0, Q = 6e-6;
  // (3) with P + F_c + b·S on the piston: S = Q/F − K·(P + F_c + b·S)/F², solved for S:
  // S = (Q/F − K·(P + F_c)/F²) / (1 + K·b/F²) = 2.0e−3 / (1 + 3.3333e−12·5e4/4e−6)
  // = 2.0e−3/1.041667.
  const double S = (Q / F - K * (P + p.coulomb_friction_N) / (F * F)) / (1.0 + K * b / (F * F));
  EXPECT_NEAR(S, 1.92e-3, 1e-9);
  auto s = make(p);
  s.set_steady(0.0, P);
  EXPECT_NEAR(settle(s, Q, P, 4.0), S, 1e-4 * S);
}

TEST(FeedSlide, SetSteadyIsAnEquilibrium) {
  auto p = base_params();
  p.damper_capacitance_m3_per_Pa = 5e-13;
  p.damper_resistance_Pa_s_per_m3 = 6e10;
  p.viscous_friction_N_s_per_m = 20000.0;
  const double F = p.piston_area_m2, K = p.leak_m3_per_s_Pa;
  const double v = 1.5e-3, P = 800.0;
  auto s = make(p);
  s.set_steady(v, P);
  // Flow that holds it: (3) solved for Q with the full piston load.
  const double load = P + p.coulomb_friction_N + p.viscous_friction_N_s_per_m * v;
  const double Q = v * F + K * load / F;
  for (int k = 0; k < 2000; ++k) {
    s.step(1e-4, Q, P);
    ASSERT_NEAR(s.state().v_m_per_s, v, 1e-9 * v) << k;
  }
  EXPECT_NEAR(s.state().p_cyl_Pa, load / F, 1e-6 * load / F);
}

TEST(FeedSlide, StictionHoldsSlideAtRest) {
  const auto p = base_params();
  const double F = p.piston_area_m2, K = p.leak_m3_per_s_Pa, P = 1000.0;
  // With the slide at rest the pressure tends to Q/K (all inflow leaks). Choose Q so that the
  // piston force F·Q/K exceeds the load by only half the Coulomb friction: it must not move.
  {
    auto s = make(p);
    s.set_steady(0.0, P);
    const double Q = K * (P + 0.5 * p.coulomb_friction_N) / F;
    for (int k = 0; k < 30000; ++k) {
      s.step(1e-4, Q, P);
      ASSERT_EQ(s.state().v_m_per_s, 0.0) << k;
    }
    EXPECT_EQ(s.state().x_m, 0.0);
    // Pressure settled at Q/K (time constant V/(B·K) = 21 ms).
    EXPECT_NEAR(s.state().p_cyl_Pa, Q / K, 1e-6 * Q / K);
  }
  {
    // Pulling load below the friction too: F·p − P = −0.5·F_c, still stuck.
    auto s = make(p);
    s.set_steady(0.0, P);
    const double Q = K * (P - 0.5 * p.coulomb_friction_N) / F;
    for (int k = 0; k < 30000; ++k) {
      s.step(1e-4, Q, P);
      ASSERT_EQ(s.state().v_m_per_s, 0.0) << k;
    }
  }
  {
    // Twice the friction: breaks away and moves forward at (3).
    auto s = make(p);
    s.set_steady(0.0, P);
    const double Q = K * (P + 2.0 * p.coulomb_friction_N) / F;
    const double S = Q / F - K * (P + p.coulomb_friction_N) / (F * F);
    EXPECT_GT(S, 0.0);
    EXPECT_NEAR(settle(s, Q, P, 4.0), S, 1e-3 * S);
    EXPECT_GT(s.state().x_m, 0.0);
  }
}

TEST(FeedSlide, HydraulicOmegaMatchesClosedForm) {
  const auto p = base_params();
  auto s = make(p);
  // ω_h = F·sqrt(B/(V·m)) = 20e−4·sqrt(1.4e9/(100e−6·50)) = 20e−4·529150 = 1058.30 rad/s.
  EXPECT_NEAR(s.hydraulic_omega(), 20e-4 * std::sqrt(1.4e9 / (100e-6 * 50.0)), 1e-9);
  EXPECT_NEAR(s.hydraulic_omega(), 1058.30, 0.01);
  // The chamber grows with the stroke: V = V0 + F·x.
  s.set_steady(0.0, 1000.0);
  for (int k = 0; k < 20000; ++k) s.step(1e-4, 6e-6, 1000.0);
  const double x = s.state().x_m;
  EXPECT_GT(x, 1e-3);
  EXPECT_NEAR(s.hydraulic_omega(), 20e-4 * std::sqrt(1.4e9 / ((100e-6 + 20e-4 * x) * 50.0)), 1e-9);
}

TEST(FeedSlide, FreeOscillationAtHydraulicOmega) {
  // No leakage, no friction: a load step excites an undamped oscillation of the oil spring and
  // the mass at ω_h. Measured period between upward zero crossings of v − v0 against 2π/ω_h.
  auto p = base_params();
  p.leak_m3_per_s_Pa = 0.0;
  p.coulomb_friction_N = 0.0;
  const double F = p.piston_area_m2, v0 = 5e-3, P = 1000.0;
  // Velocity amplitude ΔP/(m·ω_h) = 100/(50·1058) = 1.9e−3 m/s < v0: the slide never stops.
  auto s = make(p);
  s.set_steady(v0, P);
  const double dt = 1e-6;
  std::vector<double> ups;
  double prev = 0.0;
  for (int k = 0; k < 40000; ++k) {  // 40 ms ≈ 6.7 periods of 5.9 ms
    s.step(dt, v0 * F, P + 100.0);
    const double e = s.state().v_m_per_s - v0;
    if (k > 0 && prev < 0.0 && e >= 0.0) ups.push_back(k * dt);
    prev = e;
  }
  ASSERT_GE(ups.size(), 4u);
  const double period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
  EXPECT_NEAR(period, 2.0 * std::numbers::pi / s.hydraulic_omega(), 0.01 * period);
}

TEST(FeedSlide, ConfigureRejectsBadParameters) {
  FeedSlide s;
  auto p = base_params();
  p.piston_area_m2 = 0.0;
  EXPECT_THROW(s.configure(p), std::invalid_argument);
  p = base_params();
  p.mass_kg = -1.0;
  EXPECT_THROW(s.configure(p), std::invalid_argument);
  p = base_params();
  p.leak_m3_per_s_Pa = -1e-12;
  EXPECT_THROW(s.configure(p), std::invalid_argument);
  p = base_params();
  p.damper_capacitance_m3_per_Pa = 5e-13;  // without a resistance
  EXPECT_THROW(s.configure(p), std::invalid_argument);
}

// Cavitation conserves the oil (see the header): a light, undamped slide on pulsed flow
// overshoots each pulse and opens a void the next pulse must refill. F = 8 cm², V0 = 60 cm³,
// m = 60 kg, b = 2000 N·s/m (ζ ≈ 0.03 at ω_h ≈ 500 rad/s), no damper, 5 ms pulses of
// 1000 cm³/min every 50 ms (mean 100 cm³/min), 500 N load: the chamber is cavitated ≈ 12 % of
// the time.
TEST(FeedSlide, CavitationConservesOilVolume) {
  auto p = base_params();
  p.piston_area_m2 = 8e-4;
  p.dead_volume_m3 = 60e-6;
  p.leak_m3_per_s_Pa = 50e-6 / 60.0 / 1e6;
  p.mass_kg = 60.0;
  p.coulomb_friction_N = 50.0;
  p.viscous_friction_N_s_per_m = 2000.0;
  auto s = make(p);
  const double load = 500.0, dt = 1e-4, q_on = 1000e-6 / 60.0;
  s.set_steady(85e-3 / 60.0, load);
  s.reset_volume_ledger();
  const double x0 = s.state().x_m;
  long cavitated = 0;
  const long n = 50000;  // 5 s
  for (long k = 0; k < n; ++k) {
    const double q = (k % 500) < 50 ? q_on : 0.0;
    s.step(dt, q, load);
    if (s.state().void_m3 > 0.0) {
      ++cavitated;
      EXPECT_EQ(s.state().p_cyl_Pa, 0.0);
    }
  }
  EXPECT_GT(cavitated, n / 20) << "the case should cavitate";
  const auto& l = s.ledger();
  const double swept = p.piston_area_m2 * (s.state().x_m - x0);
  const double stored = l.compressed_m3 - s.state().void_m3;  // no void at the start
  // Exact ledger, step by step.
  EXPECT_NEAR(l.delivered_m3 - l.leaked_m3, swept + stored, 1e-9 * l.delivered_m3);
  // The travel is what the net inflow gives: (Q − q_leak)/F to 0.5 %.
  EXPECT_NEAR(l.delivered_m3, 5.0 * 100e-6 / 60.0, 1e-12);
  const double v = (s.state().x_m - x0) / 5.0;
  const double v_flow = (l.delivered_m3 - l.leaked_m3) / 5.0 / p.piston_area_m2;
  EXPECT_NEAR(v, v_flow, 0.005 * v_flow);
}

}  // namespace
}  // namespace lathectl::hydraulics
