#include "systems/d_gauging/gauging.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/sim/parallel.hpp"

namespace lathectl::sim {

namespace {

// Exact transition of (ξ, ε) over h and the Cholesky factor of its noise covariance.
struct Transition {
  double f11, f21, f22;         // Φ = [[f11, 0], [f21, f22]]
  double l11, l21, l22;         // Q = L·Lᵀ
  double var_xi, cov, var_eps;  // stationary P
};

Transition transition(const GaugingProcess& p, const LinearGauge& g, double h) {
  const double b = p.noise_beta_per_s, T = g.filter_s, K = g.gain_V_per_m, D = p.noise_variance_m2;
  Transition t{};
  t.f11 = std::exp(-b * h);
  t.f22 = std::exp(-h / T);
  const double c = 1.0 / T - b;
  t.f21 = std::abs(c) > 1e-12 ? -(K / T) * (t.f11 - t.f22) / c : -(K / T) * h * t.f22;
  t.var_xi = D;
  t.cov = -K * D / (1.0 + b * T);
  t.var_eps = K * K * D / (1.0 + b * T);
  // Q = P − Φ P Φᵀ
  const double q11 = t.var_xi - t.f11 * t.f11 * t.var_xi;
  const double q21 = t.cov - (t.f21 * t.var_xi * t.f11 + t.f22 * t.cov * t.f11);
  const double phip22 =
      t.f21 * t.f21 * t.var_xi + 2.0 * t.f21 * t.f22 * t.cov + t.f22 * t.f22 * t.var_eps;
  const double q22 = t.var_eps - phip22;
  t.l11 = q11 > 0.0 ? std::sqrt(q11) : 0.0;
  t.l21 = t.l11 > 0.0 ? q21 / t.l11 : 0.0;
  t.l22 = std::sqrt(std::max(q22 - t.l21 * t.l21, 0.0));
  return t;
}

struct Stationary {  // Cholesky of P for the initial draw
  double a11, a21, a22;
};
Stationary stationary(const Transition& t) {
  Stationary s{};
  s.a11 = std::sqrt(t.var_xi);
  s.a21 = s.a11 > 0.0 ? t.cov / s.a11 : 0.0;
  s.a22 = std::sqrt(std::max(t.var_eps - s.a21 * s.a21, 0.0));
  return s;
}

PartResult one_linear_part(const GaugingProcess& p, const LinearGauge& g, double s_th,
                           const Transition& tr, const Stationary& st, double h,
                           std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const double K = g.gain_V_per_m, a = p.removal_m_per_s;
  auto s_det = [&](double t) { return K * (g.intercept_m - p.allowance_m + a * (t - g.filter_s)); };
  // Expected trip: s_det(t*) = S_th; start well before it (noise and lag long settled).
  const double t_star = (s_th / K - g.intercept_m + p.allowance_m) / a + g.filter_s;
  const double corr =
      std::max(g.filter_s, p.noise_beta_per_s > 0.0 ? 1.0 / p.noise_beta_per_s : 0.0);
  const double sigma_t = std::sqrt(tr.var_eps) / (K * a);
  // Start where the threshold is ≥ 6σ away (a crossing before it has probability < 1e-9) and
  // at least one correlation time back.
  double t = std::max(0.0, t_star - corr - 6.0 * sigma_t);
  const double w1 = n01(rng), w2 = n01(rng);
  double xi = st.a11 * w1;
  double eps = st.a21 * w1 + st.a22 * w2;
  double prev = s_det(t) + eps - s_th;
  PartResult r;
  r.trip_s = std::numeric_limits<double>::quiet_NaN();
  const double t_back = p.backstop_time_s();
  const double t_end = std::min(t_star + 20.0 * corr + 20.0 * sigma_t + 10.0 * h, t_back);
  while (t < t_end) {
    const double z1 = n01(rng), z2 = n01(rng);
    const double xi_n = tr.f11 * xi + tr.l11 * z1;
    const double eps_n = tr.f21 * xi + tr.f22 * eps + tr.l21 * z1 + tr.l22 * z2;
    xi = xi_n;
    eps = eps_n;
    t += h;
    const double now = s_det(t) + eps - s_th;
    if (now >= 0.0) {
      r.trip_s = t - h * now / (now - prev);  // linear interpolation of the crossing
      break;
    }
    prev = now;
  }
  r.stop_s = r.trip_s + p.relay_response_s;
  if (!(r.stop_s <= t_back) && std::isfinite(t_back)) {  // late or never: the backstop ends it
    r.stop_s = t_back;
    r.backstop = true;
  }
  r.finished_m = p.allowance_m - a * r.stop_s;
  return r;
}

}  // namespace

double threshold_23(const LinearGauge& g, const GaugingProcess& p) {
  return design::threshold_23({g.gain_V_per_m, g.intercept_m}, p.target_m, p.removal_m_per_s,
                              g.filter_s + p.relay_response_s);
}

std::vector<PartResult> monte_carlo_linear(const GaugingProcess& p, const LinearGauge& g,
                                           double s_th, std::size_t parts, std::uint64_t seed,
                                           unsigned threads) {
  std::vector<PartResult> out(parts);
  // Step: a twentieth of the shorter of the filter lag and the noise correlation time; the
  // transition is exact, the step only sets how finely the crossing is interpolated.
  const double corr =
      std::min(g.filter_s, p.noise_beta_per_s > 0.0 ? 1.0 / p.noise_beta_per_s : g.filter_s);
  const double h = corr / 20.0;
  const Transition tr = transition(p, g, h);
  const Stationary st = stationary(tr);
  // In chunks of parts (a part is short); part i has its own stream whatever thread runs it.
  constexpr std::size_t kChunk = 1024;
  sim::parallel_for(
      (parts + kChunk - 1) / kChunk,
      [&](std::size_t c) {
        for (std::size_t i = c * kChunk; i < std::min(parts, (c + 1) * kChunk); ++i) {
          std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + i);  // one stream per part
          out[i] = one_linear_part(p, g, s_th, tr, st, h, rng);
        }
      },
      threads);
  return out;
}

std::vector<double> filter_noise_samples(const GaugingProcess& p, const LinearGauge& g,
                                         std::size_t n, double spacing_s, std::uint64_t seed) {
  const Transition tr = transition(p, g, spacing_s);
  const Stationary st = stationary(tr);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double w1 = n01(rng), w2 = n01(rng);
  double xi = st.a11 * w1, eps = st.a21 * w1 + st.a22 * w2;
  std::vector<double> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double z1 = n01(rng), z2 = n01(rng);
    const double xn = tr.f11 * xi + tr.l11 * z1;
    eps = tr.f21 * xi + tr.f22 * eps + tr.l21 * z1 + tr.l22 * z2;
    xi = xn;
    out.push_back(eps);
  }
  return out;
}

PartResult machine_part_full(const GaugingProcess& p, const sensors::VibroContactGauge::Params& gp,
                             double dt, double s_th, std::uint64_t seed, Recorder* rec,
                             std::size_t record_every, double max_time_s) {
  sensors::VibroContactGauge g;
  g.configure(gp, dt);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double rho = std::exp(-p.noise_beta_per_s * dt);
  const double kick = std::sqrt(p.noise_variance_m2 * (1.0 - rho * rho));
  double xi = std::sqrt(p.noise_variance_m2) * n01(rng);
  const double a = p.removal_m_per_s;
  const double t_expected = a > 0.0 ? (p.allowance_m - p.target_m) / a : 1.0;
  const double t_max =
      max_time_s > 0.0 ? max_time_s : 2.0 * t_expected + 10.0 * gp.filter_time_constant_s + 1.0;
  PartResult r;
  r.trip_s = r.stop_s = std::numeric_limits<double>::quiet_NaN();
  const double t_back = p.backstop_time_s();
  double stop = std::numeric_limits<double>::infinity();
  double prev = -1.0;
  double x = p.allowance_m;
  // The filter starts from its free reading; let it see the first contact (no skipped physics).
  for (std::size_t k = 0;; ++k) {
    const double t = g.time_s();
    if (t >= t_max) break;
    x = p.allowance_m - a * std::min(t, stop);
    xi = rho * xi + kick * n01(rng);
    const double s = g.step(x + xi);
    const double now = s - s_th;
    // The relay arms once the signal has settled below the threshold after the first contact.
    if (std::isnan(r.trip_s) && t > 5.0 * gp.filter_time_constant_s && prev < 0.0 && now >= 0.0) {
      r.trip_s = t + dt * (1.0 - now / (now - prev));
      if (r.trip_s + p.relay_response_s < stop) {
        stop = r.trip_s + p.relay_response_s;
        r.stop_s = stop;
      }
    }
    prev = now;
    if (t + dt >= t_back && t_back < stop) {  // x reaches the limit position first
      stop = t_back;
      r.stop_s = stop;
      r.backstop = true;
    }
    if (rec && k % record_every == 0) {
      const std::array<double, 5> row{t, x * 1e6, (x + xi) * 1e6, s, g.probe_position_m() * 1e6};
      rec->push_row(row);
    }
    if (t > stop + 5.0 * gp.filter_time_constant_s) break;
  }
  r.finished_m = std::isfinite(stop) ? p.allowance_m - a * stop : x;
  return r;
}

SignalLevel full_model_signal(const sensors::VibroContactGauge::Params& gp, double dt, double x,
                              double settle_s, double average_s) {
  const auto l = sensors::VibroContactGauge::settled_signal(gp, dt, x, settle_s, average_s);
  return {l.mean_V, l.ripple_V};
}

}  // namespace lathectl::sim
