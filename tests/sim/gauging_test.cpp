// In-process gauging, system D (src/systems/d_gauging/rig.hpp): threshold (23), the exact
// (ξ, ε) Gauss–Markov transition against the seed's (25), the linearised Monte Carlo of finished
// sizes, and the full electromechanical part against the linear predictions.
//
// Process defaults: m_x = 200 µm, a = 20 µm/s, x_k = 50 µm, D = 4e−12 m² (σ = 2 µm), β = 5 1/s,
// t_r = 0.02 s. Gauge: K = 19843.93 V/m, A0 = 289.63 µm (default transducer), T_f = 0.1 s.
//   (23) S_th = K·(A0 − x_k − a(T_f + t_r)) = 19843.93·(289.629 − 50 − 2.4)e−6 = 4.70755 V
//   (25) Var ε = D·K²/(1 + βT_f) = 4e−12·3.93782e8/1.5 = 1.05008e−3 V², σ_ε = 32.405 mV
//   size scatter σ_x = sqrt(D/(1 + βT_f)) = 2/sqrt(1.5) = 1.63299 µm
//   linear trip time: S_det(t) = K·(A0 − m_x + a(t − T_f)) = S_th at t = (m_x − x_k)/a − t_r
//     = 7.5 − 0.02 = 7.48 s; removal stops at 7.5 s with x = x_k.
// Standard errors: the sample σ of N independent normals is within σ/sqrt(2N) (1e5: 0.22 %,
// 2e4: 0.5 %), so 3 % is a ≥ 6-standard-error bound for independent samples.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "systems/d_gauging/rig.hpp"

namespace lathectl::systems::d_gauging {
namespace {

LinearGauge default_linear_gauge(const sensors::VibroContactGauge::Params& gp = {}) {
  sensors::VibroContactGauge g;
  g.configure(gp, 2e-5);
  return {g.signal_gain_V_per_m(), g.free_amplitude_m(), gp.filter_time_constant_s};
}

struct Stats {
  double mean, sd;
};
Stats stats(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, std::sqrt(ss / (n - 1.0))};
}

double sigma_eps_25(const GaugingProcess& p, const LinearGauge& g) {
  return std::sqrt(p.noise_variance_m2 * g.gain_V_per_m * g.gain_V_per_m /
                   (1.0 + p.noise_beta_per_s * g.filter_s));
}

TEST(Gauging, Threshold23ClosedForm) {
  const GaugingProcess p;
  const LinearGauge g = default_linear_gauge();
  EXPECT_NEAR(threshold_23(g, p), 4.70755, 1e-5);  // worked above
  LinearGauge h{12000.0, 150e-6, 0.05};
  GaugingProcess q;
  q.target_m = 30e-6;
  q.removal_m_per_s = 8e-6;
  q.relay_response_s = 0.01;
  // 12000·(150 − 30 − 8·0.06)e−6 = 12000·119.52e−6 = 1.43424 V
  EXPECT_NEAR(threshold_23(h, q), 1.43424, 1e-12);
  q.relay_response_s = 0.0;
  q.removal_m_per_s = 0.0;
  EXPECT_NEAR(threshold_23(h, q), 12000.0 * 120e-6, 1e-12);  // = K·(A0 − x_k)
}

TEST(Gauging, FilterNoiseSigmaMatchesSeed25) {
  const GaugingProcess p;
  const LinearGauge g = default_linear_gauge();
  // 2 s apart: correlations e^(−βh) = e^−10 and e^(−h/T_f) = e^−20, independent in practice.
  const auto eps = filter_noise_samples(p, g, 100000, 2.0, 25);
  const auto s = stats(eps);
  EXPECT_NEAR(sigma_eps_25(p, g), 0.032405, 1e-6);
  EXPECT_NEAR(s.sd / sigma_eps_25(p, g), 1.0, 0.03);
  EXPECT_NEAR(s.mean, 0.0, 5.0 * sigma_eps_25(p, g) / std::sqrt(1e5));
}

// The transition is exact, so the stationary variance does not depend on the step. The 1 ms
// samples are strongly correlated (correlation times 0.2 s and 0.1 s): 8e6 of them span 8000 s,
// enough for a ~1 % standard error of the variance.
TEST(Gauging, ExactTransitionIsStepIndependent) {
  const GaugingProcess p;
  const LinearGauge g = default_linear_gauge();
  const double var25 = std::pow(sigma_eps_25(p, g), 2);
  const auto fine = stats(filter_noise_samples(p, g, 8000000, 0.001, 7));
  const auto coarse = stats(filter_noise_samples(p, g, 100000, 1.0, 8));
  EXPECT_NEAR(fine.sd * fine.sd / var25, 1.0, 0.03);
  EXPECT_NEAR(coarse.sd * coarse.sd / var25, 1.0, 0.03);
  // A different β·T_f regime (β·T_f = 10, and the degenerate β = 1/T_f case of the transition).
  GaugingProcess q;
  q.noise_beta_per_s = 100.0;
  const auto fast = stats(filter_noise_samples(q, g, 100000, 0.5, 9));
  EXPECT_NEAR(fast.sd / sigma_eps_25(q, g), 1.0, 0.03);
  q.noise_beta_per_s = 1.0 / g.filter_s;
  const auto equal = stats(filter_noise_samples(q, g, 1000000, 0.01, 10));
  EXPECT_NEAR(equal.sd / sigma_eps_25(q, g), 1.0, 0.03);
}

TEST(Gauging, WithoutNoiseThreshold23IsExact) {
  GaugingProcess p;
  p.noise_variance_m2 = 0.0;
  const LinearGauge g = default_linear_gauge();
  const auto parts = monte_carlo_linear(p, g, threshold_23(g, p), 1000, 3, 2);
  ASSERT_EQ(parts.size(), 1000u);
  for (const auto& r : parts) {
    ASSERT_TRUE(std::isfinite(r.trip_s));
    EXPECT_NEAR(r.finished_m - p.target_m, 0.0, 1e-9);
    EXPECT_NEAR(r.trip_s, 7.48, 1e-6);
    EXPECT_NEAR(r.stop_s - r.trip_s, p.relay_response_s, 1e-12);
  }
}

TEST(Gauging, MonteCarloSizeScatterMatchesSigmaX) {
  const GaugingProcess p;
  const LinearGauge g = default_linear_gauge();
  const auto parts = monte_carlo_linear(p, g, threshold_23(g, p), 20000, 11, 2);
  std::vector<double> sizes;
  for (const auto& r : parts) {
    ASSERT_TRUE(std::isfinite(r.finished_m));
    sizes.push_back(r.finished_m);
  }
  const auto s = stats(sizes);
  const double sigma_x = std::sqrt(p.noise_variance_m2 / (1.0 + p.noise_beta_per_s * g.filter_s));
  EXPECT_NEAR(sigma_x * 1e6, 1.63299, 1e-5);
  EXPECT_NEAR(s.sd / sigma_x, 1.0, 0.03);
  // The threshold hits x_k on average (first-passage bias small against σ_x).
  EXPECT_NEAR(s.mean - p.target_m, 0.0, 0.25 * sigma_x);
  RecordProperty("finished_mean_um", std::to_string(s.mean * 1e6));
  RecordProperty("finished_sd_um", std::to_string(s.sd * 1e6));
}

TEST(Gauging, MonteCarloIsReproducibleAcrossThreadCounts) {
  const GaugingProcess p;
  const LinearGauge g = default_linear_gauge();
  const double th = threshold_23(g, p);
  const auto one = monte_carlo_linear(p, g, th, 5000, 42, 1);
  const auto two = monte_carlo_linear(p, g, th, 5000, 42, 2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].trip_s, two[i].trip_s) << i;
    EXPECT_EQ(one[i].stop_s, two[i].stop_s) << i;
    EXPECT_EQ(one[i].finished_m, two[i].finished_m) << i;
  }
  // Per part: a prefix run gives the same first parts.
  const auto prefix = monte_carlo_linear(p, g, th, 100, 42, 2);
  for (std::size_t i = 0; i < prefix.size(); ++i)
    EXPECT_EQ(prefix[i].finished_m, one[i].finished_m);
  // Another seed gives other parts.
  const auto other = monte_carlo_linear(p, g, th, 100, 43, 1);
  EXPECT_NE(other[0].finished_m, one[0].finished_m);
}

// Full model, no noise, threshold from the linearisation (A0 and K of the transducer).
// Measured at dt = 2e−5 s: default transducer/process, trip 7.4629 s (linear 7.48 s), finished
// 50.34 µm (target 50); the `design gauge` CLI transducer (a_f = 2.11e8, h = 1.382, k = 9554) with
// m_x = 250 µm, x_k = 100 µm: trip 7.4026 s, finished 101.55 µm.
TEST(Gauging, FullModelMatchesLinearPredictionWithoutNoise) {
  GaugingProcess p;
  p.noise_variance_m2 = 0.0;
  const sensors::VibroContactGauge::Params gp;
  const LinearGauge g = default_linear_gauge(gp);
  const auto r = machine_part_full(p, gp, 2e-5, threshold_23(g, p), 1);
  ASSERT_TRUE(std::isfinite(r.trip_s));
  const double t_linear = (p.allowance_m - p.target_m) / p.removal_m_per_s - p.relay_response_s;
  EXPECT_NEAR(r.trip_s, t_linear, 0.5);
  EXPECT_NEAR(r.finished_m, p.target_m, 5e-6);
  EXPECT_NEAR(r.stop_s - r.trip_s, p.relay_response_s, 1e-12);
  EXPECT_NEAR(r.finished_m, p.allowance_m - p.removal_m_per_s * r.stop_s, 1e-15);

  sensors::VibroContactGauge::Params cli = gp;
  cli.force_coefficient_N_per_Wb2 = 2.11e8;
  cli.probe_damping_N_s_per_m = 1.382;
  cli.probe_stiffness_N_per_m = 9554.0;
  p.allowance_m = 250e-6;
  p.target_m = 100e-6;
  const LinearGauge gc = default_linear_gauge(cli);
  const auto rc = machine_part_full(p, cli, 2e-5, threshold_23(gc, p), 1);
  ASSERT_TRUE(std::isfinite(rc.trip_s));
  EXPECT_NEAR(rc.trip_s, t_linear, 0.5);
  EXPECT_NEAR(rc.finished_m, p.target_m, 5e-6);
}

TEST(Gauging, FullModelStaticCalibrationNearLinear) {
  const sensors::VibroContactGauge::Params gp;
  const LinearGauge g = default_linear_gauge(gp);
  const double A0 = g.intercept_m, K = g.gain_V_per_m;
  const double s = full_model_mean_signal(gp, 2e-5, 0.5 * A0);
  EXPECT_NEAR(s / (K * (A0 - 0.5 * A0)), 1.0, 0.05);  // measured 1.031
  // No contact: K·A0 (measured 0.9973).
  EXPECT_NEAR(full_model_mean_signal(gp, 2e-5, -1e-4) / (K * A0), 1.0, 0.01);
}

}  // namespace
}  // namespace lathectl::systems::d_gauging
