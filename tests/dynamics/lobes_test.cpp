// Stability lobes, validated layer by layer (system B, part 1).
#include "lathectl/dynamics/lobes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>

#include "systems/b_chatter/lobes.hpp"

using namespace lathectl::dynamics;

namespace {
// The example mode: k = 2.26e8 N/m, ζ = 0.012, f_n = 250 Hz, θ = 30°, K_f = 1000 N/mm².
ChatterSystem sdof() {
  ChatterSystem s;
  s.kf_N_per_m2 = 1e9;
  s.modes = {{2.26e8, 0.012, 250.0, 30.0 * std::numbers::pi / 180.0}};
  return s;
}
}  // namespace

// Closed form (Altintas, Manufacturing Automation, 2nd ed., eq. 3.30 for SDOF): the minimum of
// −1/(2K_f Re Φ) is b = 2kζ(1+ζ)/(K_f cos²θ) at ω = ω_n√(1+2ζ):
// 2·2.26e8·0.012·1.012/(1e9·0.75) = 7.318784e-3 m, 250·√1.024 = 252.982 Hz.
TEST(Lobes, FrequencyDomainMatchesSdofClosedForm) {
  const auto fd = frequency_domain_lobes(sdof(), 2000, 14000, 40, 20000);
  EXPECT_NEAR(fd.critical_depth_m, 7.318784e-3, 1e-6 * 7.318784e-3);
  EXPECT_NEAR(fd.critical_chatter_Hz, 252.982, 0.05);
  ASSERT_GE(fd.lobes.size(), 5u);
  // Each lobe's minimum lies at n = 60 f_c / (N + ε/2π) with the same depth.
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(fd.lobes[i].minimum.depth_m, 7.318784e-3, 1e-5);
}

// Process damping along the chip thickness adds c·cos²θ to the mode's damping: Φ/(1 + jωcΦ) of
// an SDOF is the same mode with ζ' = ζ + c·ω_n·cos²θ/(2k). Each damped lobe point (n, b, f) must
// then be an undamped lobe point of that mode with c = C·b/n: b = −1/(2K_f Re Φ'), and n from the
// phase, the closed form of the lobe equations. C is the B rig's linear indentation coefficient
// for K_sp = 4·10¹³ N/m³, VB = 0.1 mm, D = 50 mm, κ = 90°: 60·K_sp·VB²/(4π·D).
TEST(Lobes, ProcessDampingIsTheModesOwnDampingAtEachLobePoint) {
  auto sys = sdof();
  constexpr double kPi = std::numbers::pi;
  sys.process_damping_C = 60.0 * 4e13 * 1e-8 / (4.0 * kPi * 0.05);
  const auto fd = frequency_domain_lobes(sys, 100, 14000, 200, 4000);
  const auto plain = frequency_domain_lobes(sdof(), 100, 14000, 200, 4000);
  const auto& m = sys.modes[0];
  const double c2 = std::cos(m.angle_rad) * std::cos(m.angle_rad);
  const double wn = 2.0 * kPi * m.natural_frequency_Hz;
  std::size_t checked = 0;
  for (const auto& lobe : fd.lobes) {
    for (std::size_t i = 0; i < lobe.points.size(); i += 7) {
      const auto& p = lobe.points[i];
      const double c = sys.process_damping_C * p.depth_m / p.speed_rpm;
      const double zeta = m.damping_ratio + c * wn * c2 / (2.0 * m.stiffness_N_per_m);
      const double w = 2.0 * kPi * p.chatter_Hz, r = w / wn;
      const std::complex<double> phi =
          c2 / (m.stiffness_N_per_m * std::complex<double>(1.0 - r * r, 2.0 * zeta * r));
      EXPECT_NEAR(p.depth_m, -1.0 / (2.0 * sys.kf_N_per_m2 * phi.real()), 1e-9 * p.depth_m);
      double eps = std::fmod(3.0 * kPi + 2.0 * std::atan2(phi.imag(), phi.real()), 2.0 * kPi);
      if (eps <= 0.0) eps += 2.0 * kPi;
      EXPECT_NEAR(p.speed_rpm, 60.0 * w / (eps + 2.0 * kPi * lobe.N), 1e-9 * p.speed_rpm);
      ++checked;
    }
  }
  EXPECT_GT(checked, 50u);
  // Damping only adds, and more at lower speeds (c = C·b/n): every lobe's minimum at or above
  // the undamped limit 2kζ(1+ζ)/(K_f cos²θ), rising lobe by lobe towards low speed, and nearly
  // the undamped limit at the top of the range.
  ASSERT_FALSE(fd.lobes.empty());
  double last = 0.0;
  const Lobe* lowest = nullptr;
  for (const auto& lobe : fd.lobes) {
    EXPECT_GE(lobe.minimum.depth_m, plain.critical_depth_m);
    if (!lobe.minimum_inside) continue;
    EXPECT_GE(lobe.minimum.depth_m, last) << "lobe " << lobe.N;
    last = lobe.minimum.depth_m;
    lowest = &lobe;
  }
  ASSERT_NE(lowest, nullptr);
  EXPECT_LT(fd.lobes.front().minimum.depth_m, 1.02 * plain.critical_depth_m);
  EXPECT_GT(lowest->minimum.depth_m, 1.5 * plain.critical_depth_m)
      << "at " << lowest->minimum.speed_rpm << " rpm";
}

TEST(Lobes, SemiDiscretizationAgreesWithFrequencyDomain) {
  const auto s = sdof();
  const auto fd = frequency_domain_lobes(s, 2000, 14000, 40, 8000);
  for (double n : {4000.0, 6500.0, 9500.0, 12000.0}) {
    const double tau = 60.0 / n;
    const int m = static_cast<int>(std::ceil(tau * 250.0 * 25.0));
    const double b_fd = envelope_depth(fd, n);
    const double b_sd = sd_limit_depth(s, n, 3.0 * b_fd, m, 1e-4);
    EXPECT_NEAR(b_sd / b_fd, 1.0, 0.03) << "n = " << n;
  }
}

TEST(Lobes, SpectralRadiusCrossesOneAtTheLimit) {
  const auto s = sdof();
  const double n = 9500.0;
  const double b = sd_limit_depth(s, n, 0.05, 60, 1e-5);
  EXPECT_LT(spectral_radius_sd(s, n, 0.99 * b, 60), 1.0);
  EXPECT_GT(spectral_radius_sd(s, n, 1.01 * b, 60), 1.0);
}

// At the lobe minima the time-domain simulation (with the tool leaving the cut) must decay 3 %
// below the limit and grow 3 % above it.
TEST(Lobes, TimeDomainGrowsAboveAndDecaysBelowAtLobeMinima) {
  const auto s = sdof();
  const auto fd = frequency_domain_lobes(s, 2000, 14000, 40, 20000);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& mn = fd.lobes[i].minimum;
    const auto below = time_domain(s, mn.speed_rpm, 0.97 * mn.depth_m, 0.1e-3, 10.0, 50);
    const auto above = time_domain(s, mn.speed_rpm, 1.03 * mn.depth_m, 0.1e-3, 10.0, 50);
    EXPECT_FALSE(below.grew) << "lobe N = " << fd.lobes[i].N << ": " << below.amplitude_early_m
                             << " → " << below.amplitude_late_m;
    EXPECT_TRUE(above.grew) << "lobe N = " << fd.lobes[i].N << ": " << above.amplitude_early_m
                            << " → " << above.amplitude_late_m;
    EXPECT_LT(below.amplitude_late_m, 0.1 * below.amplitude_early_m);
  }
}

TEST(Lobes, InvalidSystemsAreRejected) {
  ChatterSystem empty;
  EXPECT_THROW(frequency_domain_lobes(empty, 1000, 2000), std::invalid_argument);
  auto s = sdof();
  EXPECT_THROW(frequency_domain_lobes(s, 2000, 1000), std::invalid_argument);
  s.modes[0].damping_ratio = 0.0;
  EXPECT_THROW(frequency_domain_lobes(s, 1000, 2000), std::invalid_argument);
}

// The root count by the argument principle says "unstable" exactly where the dense eigenvalue
// solve (Eigen) gives a spectral radius above 1, over stable and unstable cells, one
// and two modes, orders 1 and 5, m from 20 to 120, and right next to the boundary (±0.1 %, where
// a root sits within 10⁻⁴ of the circle); and the chart's cell is that count.
TEST(SdChart, RootCountEqualsEigenvalueCount) {
  auto two = sdof();
  two.modes.push_back({2.13e8, 0.010, 150.0, -45.0 * std::numbers::pi / 180.0});
  int unstable_cells = 0, cells = 0;
  for (const auto& s : {sdof(), two})
    for (int order : {1, 5})
      for (double n : {2100.0, 4000.0, 6500.0, 12000.0}) {
        const int m = std::max(20, static_cast<int>(std::ceil(60.0 / n * 250.0 * 7.0)));
        const double b_lim = sd_limit_depth(s, n, 0.1, m, 1e-9, order);
        for (double b : {0.0, 0.3 * b_lim, 0.999 * b_lim, 1.001 * b_lim, 1.5 * b_lim, 4.0 * b_lim}) {
          const double rho = spectral_radius_sd(s, n, b, m, order);
          const int count = sd_unstable_roots(s, n, b, m, order);
          EXPECT_EQ(count > 0, rho > 1.0) << n << " rpm, " << b << " m, ρ = " << rho;
          EXPECT_GE(count, 0);
          unstable_cells += count > 0;
          ++cells;
        }
      }
  EXPECT_GE(unstable_cells, cells / 3);
  SdChartOptions o;
  o.threads = 2;
  const auto c = sd_stability_chart(sdof(), 5000, 9000, 3, 0.012, 4, o);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      EXPECT_EQ(c.unstable(i, j), sd_unstable_roots(sdof(), c.speed_rpm[i], c.depth_m[j],
                                                    c.steps[i], o.interpolation_order));
  EXPECT_EQ(c.steps[0], sd_steps_per_delay(sdof(), 5000, 0.012, o));
  EXPECT_THROW(spectral_radius_sd(sdof(), 5000, 0.01, 30, 2), std::invalid_argument);
  EXPECT_THROW(sd_unstable_roots(sdof(), 5000, 0.01, 30, 2), std::invalid_argument);
}

// The chart boundary against the frequency-domain envelope, speed by speed, over the whole
// example range (40 speeds × 101 depths, 0..30 mm). Tolerance 1.5 %: the quintic SD at 7 steps
// per period differs from the exact boundary by ≈ 0.1 % (mean), and the boundary is read
// between depth-grid points 0.3 mm apart by linear interpolation of ρ, which misses ρ's
// curvature; measured worst here 0.5 %. (The envelope itself is exact to the FD grid.)
TEST(SdChart, BoundaryAgreesWithFrequencyDomainEnvelope) {
  const auto s = sdof();
  const auto fd = frequency_domain_lobes(s, 2000, 14000, 40, 20000);
  const auto c = sd_stability_chart(s, 2000, 14000, 40, 0.03, 101);
  int compared = 0;
  for (std::size_t i = 0; i < c.speed_rpm.size(); ++i) {
    const double b_fd = envelope_depth(fd, c.speed_rpm[i]);
    if (!std::isfinite(b_fd)) continue;  // the range's ends: no lobe brackets them
    if (b_fd > c.depth_m.back()) {
      EXPECT_TRUE(!std::isfinite(c.boundary_depth_m[i]) ||
                  c.boundary_depth_m[i] > 0.985 * c.depth_m.back())
          << c.speed_rpm[i];
      continue;
    }
    EXPECT_NEAR(c.boundary_depth_m[i] / b_fd, 1.0, 0.015) << "n = " << c.speed_rpm[i];
    ++compared;
  }
  EXPECT_GE(compared, 20);
  // Below the absolute limit every cell is stable.
  for (std::size_t i = 0; i < c.speed_rpm.size(); ++i)
    for (std::size_t j = 0; c.depth_m[j] < 0.98 * fd.critical_depth_m; ++j)
      EXPECT_EQ(c.unstable(i, j), 0);
}

// Order of convergence: at the same m the cubic and quintic interpolations are far closer to the
// exact limit than the linear one (errors ∝ Δt⁴, Δt⁶ against Δt²). Measured at 6500 rpm,
// m = 20 (5 steps per period): linear +3.1 %, cubic +0.34 %, quintic +0.043 %.
TEST(SdChart, HigherOrderInterpolationConvergesFaster) {
  const auto s = sdof();
  const auto fd = frequency_domain_lobes(s, 2000, 14000, 40, 20000);
  const double n = 6500.0, b_fd = envelope_depth(fd, n);
  double e[6] = {};
  for (int order : {1, 3, 5}) {
    SdChartOptions o;
    o.interpolation_order = order;
    const auto c = sd_stability_chart(s, n, n + 1.0, 2, 2.0 * b_fd, 401, o);
    EXPECT_EQ(c.steps[0], 20);  // the minimum per delay: 60/6500·250·7 = 16 steps
    e[order] = std::abs(c.boundary_depth_m[0] / b_fd - 1.0);
  }
  EXPECT_LT(e[3], 0.3 * e[1]) << e[1] << " " << e[3];
  EXPECT_LT(e[5], 0.5 * e[3]) << e[3] << " " << e[5];
  EXPECT_LT(e[5], 0.002);
}

// A slow spindle and a high mode (examples/machines/b_slow_high_freq.toml: 650 Hz at
// 500–4000 rpm, 10 to 78 vibrations per revolution, m up to 546 steps per delay), whose chart by
// the dense eigenvalue solve took 7.5 min; its cost now goes to the benchmark
// (BM_Lobes_SdChartMachine). Here its accuracy: the chart's boundary within 0.5 % of the exact
// frequency-domain envelope at every speed where the envelope lies inside the chart, and the
// steps per delay not capped below 7 per period.
TEST(SdChart, SlowHighFrequencyMachineAgreesWithFrequencyDomain) {
  const auto in = lathectl::systems::b_chatter::load_lobes_input(
      LATHECTL_SOURCE_DIR "/examples/machines/b_slow_high_freq.toml");
  const auto fd =
      frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes, 40000);
  const double top = 4.0 * fd.critical_depth_m;
  SdChartOptions o;
  o.threads = 2;
  const auto c = sd_stability_chart(in.system, in.min_rpm, in.max_rpm, 60, top, 100, o);
  EXPECT_EQ(c.steps.front(), static_cast<int>(std::ceil(60.0 / 500.0 * 650.0 * 7.0)));
  int compared = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < c.speed_rpm.size(); ++i) {
    const double b_fd = envelope_depth(fd, c.speed_rpm[i]);
    if (!std::isfinite(b_fd) || b_fd > 0.98 * top) continue;
    EXPECT_NEAR(c.boundary_depth_m[i] / b_fd, 1.0, 0.005) << "n = " << c.speed_rpm[i];
    worst = std::max(worst, std::abs(c.boundary_depth_m[i] / b_fd - 1.0));
    ++compared;
  }
  EXPECT_GE(compared, 55);
  RecordProperty("worst_rel_difference", std::to_string(worst));
}

// envelope_depth by binary search in the lobes' monotone runs gives exactly (bit for bit) what
// the scan over every lobe segment gives: at 401 speeds of b_part's 60 dense lobes, at the
// lobe points' own speeds (shared ends of two segments) and outside the range.
TEST(Lobes, IndexedEnvelopeEqualsScan) {
  const auto in =
      lathectl::systems::b_chatter::load_lobes_input(LATHECTL_SOURCE_DIR "/examples/machines/b_part.toml");
  const auto fd = frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes, 40000);
  ASSERT_FALSE(fd.envelope_runs.empty());
  auto scan = fd;
  scan.envelope_runs.clear();
  std::vector<double> speeds{0.0, in.min_rpm - 1.0, in.max_rpm + 1.0,
                             std::numeric_limits<double>::quiet_NaN()};
  for (int k = 0; k <= 400; ++k)
    speeds.push_back(in.min_rpm + (in.max_rpm - in.min_rpm) * k / 400.0);
  for (const auto& l : fd.lobes)
    for (std::size_t k = 0; k < l.points.size(); k += 101) speeds.push_back(l.points[k].speed_rpm);
  int finite = 0;
  for (double n : speeds) {
    const double a = envelope_depth(fd, n), b = envelope_depth(scan, n);
    EXPECT_TRUE(a == b || (std::isinf(a) && std::isinf(b))) << n << ": " << a << " vs " << b;
    finite += std::isfinite(a);
  }
  EXPECT_GT(finite, 400);
}

TEST(SdChart, BadGridIsRejected) {
  EXPECT_THROW(sd_stability_chart(sdof(), 2000, 1000, 10, 0.01, 10), std::invalid_argument);
  EXPECT_THROW(sd_stability_chart(sdof(), 1000, 2000, 1, 0.01, 10), std::invalid_argument);
  EXPECT_THROW(sd_stability_chart(sdof(), 1000, 2000, 10, 0.0, 10), std::invalid_argument);
  SdChartOptions o;
  o.interpolation_order = 2;
  EXPECT_THROW(sd_stability_chart(sdof(), 1000, 2000, 10, 0.01, 10, o), std::invalid_argument);
}

// With depths near the denormals (a stiffness of 1e-300 N/m) the bisections' midpoint
// stops moving; they end anyway (they hung), and a top of inf is refused, not bisected.
TEST(SdBisection, EndsAtDenormalDepths) {
  ChatterSystem s;
  s.kf_N_per_m2 = 2e9;
  s.modes = {{1e-300, 0.03, 800.0, 0.0}};
  const double b = sd_limit_depth(s, 2000.0, 1e-305, 30, 1e-3, 5);
  EXPECT_FALSE(std::isnan(b));
  EXPECT_THROW((void)sd_limit_depth(s, 2000.0, std::numeric_limits<double>::infinity(), 30),
               std::invalid_argument);
  SdChartOptions o;
  o.threads = 1;
  const auto c = sd_stability_chart(s, 1000.0, 3000.0, 2, 1e-305, 3, o);
  EXPECT_EQ(c.boundary_depth_m.size(), 2u);
}
