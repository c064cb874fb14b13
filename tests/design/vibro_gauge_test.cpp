// Linearised vibro-contact gauging of seed 003 (include/lathectl/design/vibro_gauge.hpp),
// (20)-(25), against closed forms computed here from the inputs and worked by hand for the
// defaults.
//
// GaugeInput defaults: V = 24 V, 50 Hz, W = 1000, r = 50 Ω, L = 0.5 H, a_f = 2e8 N/Wb², M = 0.02
// kg, h = 1.4 N·s/m, k = 9500 N/m, K_g = 50 V/(m/s), T_g = 0.2 ms, T_f = 0.1 s, t_r = 0.02 s; m_x =
// 200 µm, a = 20 µm/s, x_k = 50 µm, D = 4e−12 m² (σ = 2 µm), β = 5 1/s.
//   ω = 314.159 rad/s, ωL = 157.080 Ω, |Z_coil| = sqrt(50² + 157.080²) = 164.846 Ω
//   i_m = 24/164.846 = 0.145591 A, Φ_m = L·i_m/W = 7.27955e−5 Wb
//   2ω component of a_f·Φ²: a_f·Φ_m²/2 = 2e8·5.29918e−9/2 = 0.529918 N
//   2ω = 628.319 rad/s: k − M(2ω)² = 9500 − 7895.68 = 1604.32 N/m, h·2ω = 879.646 N/m
//   |k − M(2ω)² + j·h·2ω| = sqrt(1604.32² + 879.646²) = 1829.65 N/m
//   A0 = 0.529918/1829.65 = 2.89629e−4 m = 289.63 µm; static offset 0.529918/9500 = 55.781 µm
//   K = (2/π)·50·628.319/sqrt(1 + (628.319·2e−4)²) = 20000/sqrt(1.0157914) = 20000/1.0078648
//     = 19843.93 V/m = 19.844 mV/µm
//   K·(A0 − x_k) = 19843.93·239.629e−6 = 4.75517 V
//   (23) S_th = K·(A0 − x_k − a(T_f + t_r)) = 19843.93·(239.629 − 2.4)e−6 = 4.70755 V
//   (22) t_k = (m_x − x_k)/a = 150/20 = 7.5 s
//   (25) D_y = D·K²/(1 + βT_f) = 4e−12·3.93782e8/1.5 = 1.05008e−3 V²  (σ_y = 32.405 mV)
//   σ_x = sqrt(D/(1 + βT_f)) = 2 µm/sqrt(1.5) = 1.63299 µm

#include "lathectl/design/vibro_gauge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace lathectl::design {
namespace {

// Closed forms, computed independently of the library.
struct Closed {
  double A0, z_eq, K;
};
Closed closed(const GaugeInput& in) {
  const double w = 2.0 * std::numbers::pi * in.supply_Hz;
  const double L = in.coil_inductance_H, r = in.coil_resistance_ohm;
  const double phi_m = L * in.supply_V / (in.coil_turns * std::sqrt(r * r + w * w * L * L));
  const double f2 = in.force_coefficient_N_per_Wb2 * phi_m * phi_m / 2.0;
  const double w2 = 2.0 * w;
  const std::complex<double> z(in.probe_stiffness_N_per_m - in.probe_mass_kg * w2 * w2,
                               in.probe_damping_N_s_per_m * w2);
  const double K = 2.0 / std::numbers::pi * in.generator_V_per_m_per_s * w2 /
                   std::sqrt(1.0 + std::pow(w2 * in.generator_time_constant_s, 2));
  return {f2 / std::abs(z), f2 / in.probe_stiffness_N_per_m, K};
}

TEST(DesignVibroGauge, DefaultsMatchHandWorkedValues) {
  const GaugeInput in;
  const auto r = gauge(in);
  EXPECT_NEAR(r.free_amplitude_m * 1e6, 289.63, 0.01);
  EXPECT_NEAR(r.static_offset_m * 1e6, 55.781, 0.001);
  EXPECT_NEAR(r.signal_gain_V_per_m, 19843.93, 0.01);
  EXPECT_NEAR(r.signal_at_target_V, 4.75517, 1e-5);
  EXPECT_NEAR(r.threshold_V, 4.70755, 1e-5);
  EXPECT_NEAR(r.end_time_s, 7.5, 1e-12);
  EXPECT_NEAR(r.noise_variance_V2, 1.05008e-3, 1e-8);
  EXPECT_NEAR(std::sqrt(r.noise_variance_V2) * 1e3, 32.405, 0.001);
  EXPECT_NEAR(r.size_sigma_m * 1e6, 1.63299, 1e-5);
}

// Every output against its formula, for the defaults and for a different transducer and process.
void expect_closed_forms(const GaugeInput& in) {
  const auto r = gauge(in);
  const auto c = closed(in);
  const double T = in.filter_time_constant_s;
  EXPECT_NEAR(r.free_amplitude_m / c.A0, 1.0, 1e-12);
  EXPECT_NEAR(r.static_offset_m / c.z_eq, 1.0, 1e-12);
  EXPECT_NEAR(r.signal_gain_V_per_m / c.K, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(r.intercept_m, r.free_amplitude_m);  // B0/q1 = A0, the seed's approximation
  EXPECT_NEAR(r.signal_at_target_V, c.K * (c.A0 - in.target_m), 1e-12);
  EXPECT_NEAR(r.threshold_V,
              c.K * (c.A0 - in.target_m - in.removal_m_per_s * (T + in.relay_response_s)), 1e-12);
  EXPECT_NEAR(r.end_time_s, (in.allowance_m - in.target_m) / in.removal_m_per_s, 1e-12);
  const double Dy = in.noise_variance_m2 * c.K * c.K / (1.0 + in.noise_beta_per_s * T);
  EXPECT_NEAR(r.noise_variance_V2 / Dy, 1.0, 1e-12);
  // σ_x is σ_y converted back to size by 1/K.
  EXPECT_NEAR(r.size_sigma_m, std::sqrt(r.noise_variance_V2) / r.signal_gain_V_per_m, 1e-18);
  EXPECT_NEAR(r.size_sigma_m, std::sqrt(in.noise_variance_m2 / (1.0 + in.noise_beta_per_s * T)),
              1e-18);
}

TEST(DesignVibroGauge, OutputsMatchClosedForms) {
  expect_closed_forms(GaugeInput{});
  GaugeInput cli;  // the `lathectl design gauge` defaults
  cli.force_coefficient_N_per_Wb2 = 2.11e8;
  cli.probe_damping_N_s_per_m = 1.382;
  cli.probe_stiffness_N_per_m = 9554.0;
  cli.allowance_m = 250e-6;
  cli.target_m = 100e-6;
  expect_closed_forms(cli);
  GaugeInput other;
  other.supply_V = 36.0;
  other.supply_Hz = 60.0;
  other.coil_turns = 800.0;
  other.coil_resistance_ohm = 30.0;
  other.coil_inductance_H = 0.3;
  other.probe_mass_kg = 0.015;
  other.probe_damping_N_s_per_m = 2.0;
  other.probe_stiffness_N_per_m = 12000.0;
  other.generator_V_per_m_per_s = 30.0;
  other.generator_time_constant_s = 0.0;
  other.filter_time_constant_s = 0.05;
  other.relay_response_s = 0.0;
  other.allowance_m = 120e-6;
  other.removal_m_per_s = 5e-6;
  other.target_m = 10e-6;
  other.noise_variance_m2 = 1e-12;
  other.noise_beta_per_s = 20.0;
  expect_closed_forms(other);
}

TEST(DesignVibroGauge, FilterLagAndRelayLowerTheThreshold) {
  GaugeInput in;
  const auto base = gauge(in);
  in.filter_time_constant_s *= 2.0;  // +0.1 s of lag → 2 µm more removed before the relay acts
  const auto slow = gauge(in);
  EXPECT_NEAR(base.threshold_V - slow.threshold_V, base.signal_gain_V_per_m * 20e-6 * 0.1, 1e-12);
  // A longer filter also smooths more: D_y falls as 1/(1 + βT_f).
  EXPECT_NEAR(slow.noise_variance_V2 / base.noise_variance_V2, 1.5 / 2.0, 1e-12);
}

TEST(DesignVibroGauge, NoRemovalNeverEnds) {
  GaugeInput in;
  in.removal_m_per_s = 0.0;
  const auto r = gauge(in);
  EXPECT_TRUE(std::isinf(r.end_time_s));
  EXPECT_NEAR(r.threshold_V, r.signal_at_target_V, 1e-15);  // nothing removed during the lag
}

TEST(DesignVibroGauge, InvalidInputsThrow) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto bad = [](auto&& mutate) {
    GaugeInput in;
    mutate(in);
    return in;
  };
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.relay_response_s = -0.01; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.removal_m_per_s = -1e-6; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.noise_variance_m2 = -1e-12; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.noise_beta_per_s = -1.0; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([nan](GaugeInput& i) { i.allowance_m = nan; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.target_m = INFINITY; })), std::invalid_argument);
  // Transducer parameters are checked by the transducer model.
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.supply_V = 0.0; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.supply_Hz = -50.0; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.coil_turns = 0.0; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.coil_inductance_H = 0.0; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.probe_mass_kg = 0.0; })), std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.probe_stiffness_N_per_m = -1.0; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.probe_damping_N_s_per_m = -0.1; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.generator_V_per_m_per_s = 0.0; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.generator_time_constant_s = -1e-4; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([](GaugeInput& i) { i.filter_time_constant_s = 0.0; })),
               std::invalid_argument);
  EXPECT_THROW(gauge(bad([nan](GaugeInput& i) { i.force_coefficient_N_per_Wb2 = nan; })),
               std::invalid_argument);
  EXPECT_NO_THROW(gauge(GaugeInput{}));
}

// Regression (found by this test, fixed; src/design/vibro_gauge.cpp): gauge() used to
// configure the full transducer model with a dummy step 1e−3/(2π·f·20) and a dummy contact
// stiffness of 1 N/m so its step checks pass, but the contact check dt·sqrt(k_c/M) ≤ 0.5 depends on
// M as well as f. With a slow supply and a light probe (here f = 1e−3 Hz, M = 0.2 g: dt = 7.96e−3
// s, dt·sqrt(1/2e−4) = 0.56) the formulas, which need no step, are refused with "step too coarse
// for the contact stiffness (use step_s ≤ …)", a step the caller never chose (`lathectl design
// gauge --supply-Hz 1e-3 --probe-mass-g 0.2` prints that). Same with f = 50 Hz for M < 1e−13 kg.
TEST(DesignVibroGauge, FormulasNeedNoStep) {
  GaugeInput in;
  in.supply_Hz = 1e-3;
  in.probe_mass_kg = 2e-4;
  GaugeResult r;
  ASSERT_NO_THROW(r = gauge(in));
  const auto c = closed(in);
  EXPECT_NEAR(r.free_amplitude_m / c.A0, 1.0, 1e-12);
  EXPECT_NEAR(r.signal_gain_V_per_m / c.K, 1.0, 1e-12);
}

// The safe range from the full model: the bounce floor, and the near-A0 target refused.
TEST(DesignVibroGauge, SafeRangeFromTheFullModel) {
  GaugeInput in;
  in.force_coefficient_N_per_Wb2 = 2.11e8;  // the d_gauging transducer (A0 = 298.7 µm)
  in.probe_damping_N_s_per_m = 1.382;
  in.probe_stiffness_N_per_m = 9554.0;
  in.allowance_m = 250e-6;
  in.target_m = 100e-6;
  const auto r = gauge(in);
  EXPECT_TRUE(r.range.contains(r.threshold_V));
  EXPECT_GT(r.range.floor_V, 0.9);  // the probe's bounce: measured 1.19 V
  EXPECT_LT(r.range.floor_V, 1.5);
  EXPECT_NEAR(r.range.free_V / (r.signal_gain_V_per_m * r.free_amplitude_m), 1.0, 0.01);
  EXPECT_GT(r.range.low_V, r.range.floor_V);
  EXPECT_LT(r.range.high_V, r.range.free_V);
  EXPECT_GT(r.largest_target_m, 200e-6);
  EXPECT_LT(r.largest_target_m, 250e-6);
  in.allowance_m = 290e-6;  // the new user: target 0.85·A0
  in.target_m = 254e-6;
  const auto n = gauge(in);
  EXPECT_FALSE(n.range.contains(n.threshold_V));
  EXPECT_LT(n.threshold_V, n.range.low_V);
}

TEST(DesignVibroGauge, RegularityRule) {
  GaugeInput in;
  in.force_coefficient_N_per_Wb2 = 2.11e8;
  in.probe_damping_N_s_per_m = 1.382;
  in.probe_stiffness_N_per_m = 9554.0;
  in.allowance_m = 250e-6;
  in.target_m = 100e-6;
  EXPECT_FALSE(gauge(in).regular);  // the seed's lightly damped contact: period doubling
  in.contact_damping_N_s_per_m = 200.0;
  EXPECT_TRUE(gauge(in).regular);
}

}  // namespace
}  // namespace lathectl::design
