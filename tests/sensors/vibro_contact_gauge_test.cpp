// Full electromechanical vibro-contact transducer of seed 003
// (include/lathectl/sensors/vibro_contact_gauge.hpp), against closed forms computed here.
//
// Default Params: V = 24 V, 50 Hz, W = 1000, r = 50 Ω, L = 0.5 H, a_f = 2e8 N/Wb², M = 0.02 kg,
// h = 1.4 N·s/m, k = 9500 N/m, k_c = 1e6 N/m, c_c = 5 N·s/m, K_g = 50 V/(m/s), T_g = 0.2 ms,
// T_f = 0.1 s.
//   Φ_m = L·V/(W·sqrt(r² + ω²L²)) = 0.5·24/(1000·164.846) = 7.27955e−5 Wb
//   A0 = (a_f·Φ_m²/2)/|k − M(2ω)² + j·h·2ω| = 0.529918 N/1829.65 N/m = 289.63 µm
//   K = (2/π)·K_g·2ω/sqrt(1 + (2ωT_g)²) = 20000/1.0078648 = 19843.93 V/m
// The mean of a rectified sinusoid of amplitude U is (2/π)·U; the generator voltage of a probe
// swinging A·sin 2ωt has amplitude K_g·2ω·A/sqrt(1 + (2ωT_g)²), hence S̄ = K·A.
//
// Measured (dt = 2e−5 s): the free amplitude settles at 0.9973·A0 and S̄ at 0.9973·K·A0 (the
// semi-implicit Euler's first-order error; 0.9987 at dt = 1e−5). In contact, at x = 0.5·A0 the
// probe penetrates the surface by up to 10.8 µm with k_c = 1e6 N/m (impact at ≈ 0.1 m/s) and by
// 3.6 µm with k_c = 1e7 N/m (where S̄ = 0.499·K·A0, against 0.516 at 1e6).
// S̄(x)/(K·(A0 − x)) is 0.98…1.03 for x ≤ 0.5·A0, 1.10 at 0.6·A0, 1.13 at 0.8·A0 and 1.70 at
// 0.9·A0: the seed's "amplitude A0 − x" holds in the lower half.

#include "lathectl/sensors/vibro_contact_gauge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>

namespace lathectl::sensors {
namespace {

constexpr double kDt = 2e-5;

double closed_a0(const VibroContactGauge::Params& p) {
  const double w = 2.0 * std::numbers::pi * p.supply_Hz;
  const double L = p.coil_inductance_H, r = p.coil_resistance_ohm;
  const double phi_m = L * p.supply_V / (p.coil_turns * std::sqrt(r * r + w * w * L * L));
  const double w2 = 2.0 * w;
  const std::complex<double> z(p.probe_stiffness_N_per_m - p.probe_mass_kg * w2 * w2,
                               p.probe_damping_N_s_per_m * w2);
  return p.force_coefficient_N_per_Wb2 * phi_m * phi_m / 2.0 / std::abs(z);
}

double closed_gain(const VibroContactGauge::Params& p) {
  const double w2 = 4.0 * std::numbers::pi * p.supply_Hz;
  return 2.0 / std::numbers::pi * p.generator_V_per_m_per_s * w2 /
         std::sqrt(1.0 + std::pow(w2 * p.generator_time_constant_s, 2));
}

VibroContactGauge make(const VibroContactGauge::Params& p = {}, double dt = kDt) {
  VibroContactGauge g;
  g.configure(p, dt);
  return g;
}

struct Settled {
  double mean_S = 0.0;  // mean filtered signal over the averaging window
  double z_min = 1e9, z_max = -1e9;
  double max_penetration = -1e9;  // z − surface, surface = z_eq + A0 − x
};

// Settle for `settle_s`, then average over `average_s` at fixed x.
Settled run_fixed(VibroContactGauge& g, double x, double settle_s = 0.8, double average_s = 0.4) {
  const auto n_settle = static_cast<int>(settle_s / kDt), n_avg = static_cast<int>(average_s / kDt);
  for (int k = 0; k < n_settle; ++k) g.step(x);
  Settled s;
  const double surface = g.static_offset_m() + g.free_amplitude_m() - x;
  for (int k = 0; k < n_avg; ++k) {
    s.mean_S += g.step(x);
    const double z = g.probe_position_m();
    s.z_min = std::min(s.z_min, z);
    s.z_max = std::max(s.z_max, z);
    s.max_penetration = std::max(s.max_penetration, z - surface);
  }
  s.mean_S /= n_avg;
  return s;
}

TEST(VibroContactGauge, FreeAmplitudeAndGainMatchClosedForm) {
  VibroContactGauge::Params p;
  auto g = make(p);
  EXPECT_NEAR(g.free_amplitude_m() / closed_a0(p), 1.0, 1e-12);
  EXPECT_NEAR(g.free_amplitude_m() * 1e6, 289.63, 0.01);  // worked by hand above
  EXPECT_NEAR(g.signal_gain_V_per_m() / closed_gain(p), 1.0, 1e-12);
  EXPECT_NEAR(g.signal_gain_V_per_m(), 19843.93, 0.01);
  EXPECT_NEAR(g.static_offset_m() * 1e6, 0.529918 / 9500.0 * 1e6, 1e-3);  // DC force / k
  // A different transducer: stiffer, lighter, faster supply.
  p.supply_Hz = 60.0;
  p.probe_mass_kg = 0.012;
  p.probe_stiffness_N_per_m = 15000.0;
  p.force_coefficient_N_per_Wb2 = 3e8;
  p.generator_time_constant_s = 0.0;
  auto h = make(p);
  EXPECT_NEAR(h.free_amplitude_m() / closed_a0(p), 1.0, 1e-12);
  EXPECT_NEAR(h.signal_gain_V_per_m() / closed_gain(p), 1.0, 1e-12);
}

TEST(VibroContactGauge, WithoutContactTheMeanSignalIsKTimesA0) {
  auto g = make();
  const double KA0 = g.signal_gain_V_per_m() * g.free_amplitude_m();
  EXPECT_NEAR(g.filtered_V(), KA0, 1e-12);  // reset() starts in the free steady state
  const auto s = run_fixed(g, -50e-6, 1.0, 0.5);
  // (2/π)·amplitude of the rectified generator voltage; measured 0.9973.
  EXPECT_NEAR(s.mean_S / KA0, 1.0, 0.01);
}

TEST(VibroContactGauge, FreeOscillationAmplitudeIsA0) {
  auto g = make();
  const double A0 = g.free_amplitude_m();
  const auto s = run_fixed(g, -1.0, 1.0, 0.5);
  EXPECT_NEAR((s.z_max - s.z_min) / 2.0 / A0, 1.0, 0.01);  // measured 0.9973
  // Centred on the static deflection by the DC part of the magnet force.
  EXPECT_NEAR((s.z_max + s.z_min) / 2.0, g.static_offset_m(), 0.01 * A0);
  EXPECT_LT(s.max_penetration, 0.0);  // never reaches the (absent) surface
}

TEST(VibroContactGauge, ContactLowersTheSignalAndTheSurfaceHolds) {
  VibroContactGauge::Params p;
  auto g = make(p);
  const double A0 = g.free_amplitude_m(), K = g.signal_gain_V_per_m();
  const auto s = run_fixed(g, 0.5 * A0);
  EXPECT_LT(s.mean_S, 0.75 * K * A0);  // linear model: 0.5·K·A0; measured 0.516·K·A0
  EXPECT_GT(s.max_penetration, 0.0);   // it does touch
  // Penetration bound from the impact energy: at most the free peak speed 2ω·A0 absorbed by the
  // contact spring, v·sqrt(M/k_c), plus the peak magnet force over k_c:
  // 628.3·289.6e−6·sqrt(0.02/1e6) + 1.06/1e6 = 25.7 + 1.1 µm. Measured 10.8 µm.
  const double w2 = 4.0 * std::numbers::pi * p.supply_Hz;
  const double bound = w2 * A0 * std::sqrt(p.probe_mass_kg / p.contact_stiffness_N_per_m) +
                       2.0 * 0.529918 / p.contact_stiffness_N_per_m;
  EXPECT_LT(s.max_penetration, bound);
  EXPECT_LT(s.max_penetration, 15e-6);
  // A stiffer contact (k_c = 1e7 N/m, dt·sqrt(k_c/M) = 0.45): only a few µm.
  p.contact_stiffness_N_per_m = 1e7;
  auto stiff = make(p);
  const auto ss = run_fixed(stiff, 0.5 * A0);
  EXPECT_GT(ss.max_penetration, 0.0);
  EXPECT_LT(ss.max_penetration, 5e-6);
  EXPECT_NEAR(ss.mean_S / s.mean_S, 1.0, 0.05);  // the reading hardly depends on k_c
}

TEST(VibroContactGauge, MeanSignalFallsMonotonicallyWithX) {
  auto probe = make();
  const double A0 = probe.free_amplitude_m(), K = probe.signal_gain_V_per_m();
  double prev = INFINITY;
  for (int i = 0; i <= 8; ++i) {  // x = 0, 0.1·A0, …, 0.8·A0
    auto g = make();
    const double x = 0.1 * i * A0;
    const double s = run_fixed(g, x).mean_S;
    EXPECT_LT(s, prev) << "x = " << i * 0.1 << "·A0";
    if (i <= 5) {
      EXPECT_NEAR(s / (K * (A0 - x)), 1.0, 0.05) << "x = " << i * 0.1 << "·A0";
    }
    prev = s;
  }
}

// On a fine grid the impact oscillator shows its bifurcations: at dt = 2e−5 s S̄ rises by
// 0.047 V (0.8 % of K·A0, ≈ 2.4 µm of size) from x = 0.07·A0 to 0.08·A0, where the probe leaves
// a period-4 bouncing pattern; the step persists at dt = 1e−5 s, so it is physics of the model
// (not of the integrator). The linearised theory has no such steps; they stay small.
TEST(VibroContactGauge, FineGridStepsAgainstTheSlopeAreSmall) {
  auto probe = make();
  const double A0 = probe.free_amplitude_m(), K = probe.signal_gain_V_per_m();
  double prev = INFINITY, worst_rise = 0.0;
  for (int i = 0; i <= 80; ++i) {
    auto g = make();
    const double s = run_fixed(g, 0.01 * i * A0).mean_S;
    worst_rise = std::max(worst_rise, s - prev);
    prev = s;
  }
  EXPECT_LT(worst_rise, 0.015 * K * A0);
}

TEST(VibroContactGauge, ConfigureRejectsBadInput) {
  VibroContactGauge g;
  VibroContactGauge::Params p;
  // dt·sqrt(k_c/M) = 1e−4·sqrt(1e6/0.02) = 0.707 > 0.5 (while ω·dt = 0.031 passes).
  try {
    g.configure(p, 1e-4);
    ADD_FAILURE() << "a step too coarse for the contact stiffness was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("contact stiffness"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(g.configure(p, 0.49 / std::sqrt(p.contact_stiffness_N_per_m / p.probe_mass_kg)));
  p.contact_stiffness_N_per_m = 1e8;  // the default step is too coarse for a stiffer contact
  EXPECT_THROW(g.configure(p, kDt), std::invalid_argument);
  p = {};
  EXPECT_THROW(g.configure(p, 0.0), std::invalid_argument);
  EXPECT_THROW(g.configure(p, -kDt), std::invalid_argument);
  p.probe_mass_kg = 0.0;
  EXPECT_THROW(g.configure(p, kDt), std::invalid_argument);
  p = {};
  p.probe_damping_N_s_per_m = -1.0;
  EXPECT_THROW(g.configure(p, kDt), std::invalid_argument);
  p = {};
  p.supply_Hz = NAN;
  EXPECT_THROW(g.configure(p, kDt), std::invalid_argument);
}

// (6) and (9)-(11): gaps far larger than the excursion give back the linear model,
// the permanent magnet's pull at rest shifts the probe by F_M0/k, and a real gap changes A0.
TEST(VibroContactGauge, GapModelsReduceToTheLinearOneForLargeGaps) {
  VibroContactGauge::Params p;
  const auto st = VibroContactGauge::steady(p);
  p.magnet_gap_m = 1.0;  // 1 m: Φ varies by z/δ ≈ 3e-4
  p.pm_gap_m = 1.0;
  const auto g = make(p);
  EXPECT_NEAR(g.free_amplitude_m() / st.free_amplitude_m, 1.0, 5e-3);
  EXPECT_NEAR(g.static_offset_m() / st.static_offset_m, 1.0, 5e-3);
  p.pm_force_N = 0.5;  // F_M0/k = 0.5/9500 = 52.6 µm more
  const auto h = make(p);
  EXPECT_NEAR((h.static_offset_m() - g.static_offset_m()) * 1e6, 0.5 / 9500.0 * 1e6, 0.5);
  EXPECT_NEAR(h.free_amplitude_m() / g.free_amplitude_m(), 1.0, 5e-3);
  // δ = W²/(2·a_f·L) = 1e6/(2·2e8·0.5) = 5 mm, the gap consistent with (5) and L: the flux grows
  // as the probe closes it, the 2ω force and the amplitude with it (a few per cent).
  VibroContactGauge::Params q;
  q.magnet_gap_m = 5e-3;
  const auto k = make(q);
  EXPECT_GT(k.free_amplitude_m(), 0.95 * st.free_amplitude_m);
  EXPECT_LT(k.free_amplitude_m(), 1.10 * st.free_amplitude_m);
  q.magnet_gap_m = 0.5e-3;  // narrower than twice the crest excursion
  EXPECT_THROW(make(q), std::invalid_argument);
}

// The filters: the same mean, the 2ω ripple (here without contact: a pure rectified
// sinusoid, ripple at 4ω) far lower for two lags, nulled by the synchronous mean.
TEST(VibroContactGauge, FiltersKeepTheMeanAndCutTheRipple) {
  using F = VibroContactGauge::Params::Filter;
  VibroContactGauge::Params p;
  const auto first = VibroContactGauge::settled_signal(p, kDt, -10e-6, 1.0, 0.4);
  p.filter = F::SecondOrder;
  const auto second = VibroContactGauge::settled_signal(p, kDt, -10e-6, 1.0, 0.4);
  p.filter = F::Synchronous;
  const auto sync = VibroContactGauge::settled_signal(p, kDt, -10e-6, 1.0, 0.4);
  EXPECT_NEAR(second.mean_V / first.mean_V, 1.0, 2e-3);
  EXPECT_NEAR(sync.mean_V / first.mean_V, 1.0, 2e-3);
  // First order at 4ω = 1257 rad/s, T_f = 0.1: ripple ≈ (2/3)·mean/(4ωT_f); two lags of T_f/2:
  // a further 1/(4ω·T_f/2) ≈ 1/63.
  EXPECT_LT(second.ripple_V, first.ripple_V / 20.0);
  EXPECT_LT(sync.ripple_V, first.ripple_V / 1000.0);
  EXPECT_DOUBLE_EQ(VibroContactGauge::synchronous_window_s(p), 0.2);  // 10 periods of 50 Hz
  EXPECT_DOUBLE_EQ(VibroContactGauge::filter_lag_s(p), 0.1);
}

// (25) extended: the variance factors against their closed forms at βT_f = 0.5.
TEST(VibroContactGauge, NoiseFactorsOfTheFilters) {
  using F = VibroContactGauge::Params::Filter;
  VibroContactGauge::Params p;  // T_f = 0.1, β = 5
  EXPECT_NEAR(VibroContactGauge::filter_noise_factor(p, 5.0), 1.0 / 1.5, 1e-15);
  p.filter = F::SecondOrder;  // βτ = 0.25: (0.25 + 2)/(2·1.25²) = 0.72
  EXPECT_NEAR(VibroContactGauge::filter_noise_factor(p, 5.0), 0.72, 1e-12);
  p.filter = F::Synchronous;  // x = βT_w = 1: 2(1 − 1 + e^−1)/1 = 0.735759
  EXPECT_NEAR(VibroContactGauge::filter_noise_factor(p, 5.0), 2.0 * std::exp(-1.0), 1e-12);
}

// The Poincaré spread tells the seed's period-doubling probe from a regular one.
TEST(VibroContactGauge, PoincareSpreadShowsPeriodDoubling) {
  VibroContactGauge::Params p;
  p.force_coefficient_N_per_Wb2 = 2.11e8;
  p.probe_damping_N_s_per_m = 1.382;
  p.probe_stiffness_N_per_m = 9554.0;
  const double x = 102.4e-6;  // d_gauging's trip point
  const auto seed = VibroContactGauge::settled_signal(p, kDt, x, 1.2, 0.4);
  p.contact_damping_N_s_per_m = 200.0;
  const auto damped = VibroContactGauge::settled_signal(p, kDt, x, 1.2, 0.4);
  EXPECT_GT(seed.spread_m, 20e-6);   // measured 39-44 µm
  EXPECT_LT(damped.spread_m, 3e-6);  // measured ≈ 1 µm
}

}  // namespace
}  // namespace lathectl::sensors
