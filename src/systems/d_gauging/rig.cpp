#include "systems/d_gauging/rig.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/core/first_order_lag.hpp"
#include "lathectl/dynamics/ornstein_uhlenbeck.hpp"
#include "systems/d_gauging/machine_params.hpp"
#include "lathectl/core/parallel.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/io/progress.hpp"

namespace lathectl::systems::d_gauging {

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
  // The ramp's delay: the filter's, and the bridges' over an interrupted surface.
  const double lag = g.lag_s() + p.interruption.bridge_lag_s(g.supply_Hz);
  auto s_det = [&](double t) { return K * (g.intercept_m - p.allowance_m + a * (t - lag)); };
  // Expected trip: s_det(t*) = S_th; start well before it (noise and lag long settled).
  const double t_star = (s_th / K - g.intercept_m + p.allowance_m) / a + lag;
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
  // Until the trip and t* (ε there: the control variate of the bias calibration).
  while (t < t_end && (std::isnan(r.trip_s) || std::isnan(r.noise_at_nominal_V))) {
    const double z1 = n01(rng), z2 = n01(rng);
    const double xi_n = tr.f11 * xi + tr.l11 * z1;
    const double eps_n = tr.f21 * xi + tr.f22 * eps + tr.l21 * z1 + tr.l22 * z2;
    xi = xi_n;
    eps = eps_n;
    t += h;
    if (std::isnan(r.noise_at_nominal_V) && t >= t_star) r.noise_at_nominal_V = eps;
    const double now = s_det(t) + eps - s_th;
    if (std::isnan(r.trip_s) && now >= 0.0)
      r.trip_s = t - h * now / (now - prev);  // linear interpolation of the crossing
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

// ε = filter(−K·ξ) for the second-order and synchronous filters, by steps h: ξ exact (OU), each
// lag exact for an input linear over the step, the moving average by the trapezoid rule over a
// whole number of steps. Starts from a stationary ξ and runs a warm-up so ε is stationary too.
class FilteredNoise {
 public:
  FilteredNoise(const GaugingProcess& p, const LinearGauge& g, double h)
      : g_(g), h_(h) {
    xi_.configure(p.noise_variance_m2, p.noise_beta_per_s, h);
    const double tau = 0.5 * g.filter_s;
    lag_ = core::FirstOrderLag(h, tau);
    if (g.filter == LinearGauge::Filter::Synchronous)
      ring_.assign(static_cast<std::size_t>(std::llround(2.0 * g.lag_s() / h)) + 1, 0.0);
    warm_ = g.filter == LinearGauge::Filter::Synchronous ? 2.0 * g.lag_s() : 8.0 * tau;
  }
  // A step h for the window: a whole number of steps per window, near h0.
  static double step_for(const LinearGauge& g, double h0) {
    if (g.filter != LinearGauge::Filter::Synchronous) return h0;
    const double tw = 2.0 * g.lag_s();
    return tw / std::max(1.0, std::round(tw / h0));
  }
  void start(std::mt19937_64& rng) {
    const double in = -g_.gain_V_per_m * xi_.start(n01_(rng));
    y1_ = y2_ = in;
    std::fill(ring_.begin(), ring_.end(), in);
    sum_ = in * static_cast<double>(ring_.size());
    pos_ = 0;
    for (double t = 0.0; t < warm_; t += h_) (void)step(rng);
  }
  double step(std::mt19937_64& rng) {
    const double a = -g_.gain_V_per_m * xi_.value();
    const double b = -g_.gain_V_per_m * xi_.step(n01_(rng));
    if (ring_.empty()) {  // two lags τ = T_f/2, each exact for the linear input over the step
      const double y1_new = lag_.step_ramp(y1_, a, b, tau_over_h());
      const double y2_new = lag_.step_ramp(y2_, y1_, y1_new, tau_over_h());
      y1_ = y1_new;
      y2_ = y2_new;
      return y2_;
    }
    sum_ += b - ring_[pos_];
    ring_[pos_] = b;
    pos_ = (pos_ + 1) % ring_.size();
    const double first = ring_[pos_], last = b;  // oldest and newest of the n + 1 samples
    return (sum_ - 0.5 * (first + last)) / static_cast<double>(ring_.size() - 1);
  }

 private:
  [[nodiscard]] double tau_over_h() const { return 0.5 * g_.filter_s / h_; }
  LinearGauge g_;
  double h_, warm_ = 0.0;
  core::FirstOrderLag lag_;  // each of the two
  dynamics::OrnsteinUhlenbeck xi_;
  double y1_ = 0.0, y2_ = 0.0, sum_ = 0.0;
  std::vector<double> ring_;
  std::size_t pos_ = 0;
  std::normal_distribution<double> n01_{0.0, 1.0};
};

PartResult one_filtered_part(const GaugingProcess& p, const LinearGauge& g, double s_th,
                             FilteredNoise& noise, double h, std::mt19937_64& rng) {
  const double K = g.gain_V_per_m, a = p.removal_m_per_s, lag = g.lag_s();
  const double ramp_lag = lag + p.interruption.bridge_lag_s(g.supply_Hz);  // and the bridges'
  auto s_det = [&](double t) {
    return K * (g.intercept_m - p.allowance_m + a * (t - ramp_lag));
  };
  const double t_star = (s_th / K - g.intercept_m + p.allowance_m) / a + ramp_lag;
  const double corr = std::max(lag, p.noise_beta_per_s > 0.0 ? 1.0 / p.noise_beta_per_s : 0.0);
  const double sigma_t = std::sqrt(p.noise_variance_m2 * g.noise_factor(p.noise_beta_per_s)) / a;
  double t = std::max(0.0, t_star - corr - 6.0 * sigma_t);
  noise.start(rng);
  double prev = s_det(t) + noise.step(rng) - s_th;
  PartResult r;
  r.trip_s = std::numeric_limits<double>::quiet_NaN();
  const double t_back = p.backstop_time_s();
  const double t_end = std::min(t_star + 20.0 * corr + 20.0 * sigma_t + 10.0 * h, t_back);
  while (t < t_end && (std::isnan(r.trip_s) || std::isnan(r.noise_at_nominal_V))) {
    t += h;
    const double eps = noise.step(rng);
    if (std::isnan(r.noise_at_nominal_V) && t >= t_star) r.noise_at_nominal_V = eps;
    const double now = s_det(t) + eps - s_th;
    if (std::isnan(r.trip_s) && now >= 0.0 && prev < 0.0) r.trip_s = t - h * now / (now - prev);
    prev = now;
  }
  r.stop_s = r.trip_s + p.relay_response_s;
  if (!(r.stop_s <= t_back) && std::isfinite(t_back)) {
    r.stop_s = t_back;
    r.backstop = true;
  }
  r.finished_m = p.allowance_m - a * r.stop_s;
  return r;
}

double filtered_step(const GaugingProcess& p, const LinearGauge& g) {
  const double corr = std::min(
      {0.5 * g.filter_s, g.lag_s(), p.noise_beta_per_s > 0.0 ? 1.0 / p.noise_beta_per_s : 1.0});
  return FilteredNoise::step_for(g, corr / 10.0);
}

}  // namespace

LinearGauge linear_gauge(const design::GaugeLine& line,
                         const sensors::VibroContactGauge::Params& t) {
  return {line.gain_V_per_m, line.intercept_m, t.filter_time_constant_s, t.filter, t.supply_Hz};
}

double threshold_23(const LinearGauge& g, const GaugingProcess& p) {
  return design::threshold_23({g.gain_V_per_m, g.intercept_m}, p.target_m, p.removal_m_per_s,
                              g.lag_s() + p.relay_response_s +
                                  p.interruption.bridge_lag_s(g.supply_Hz));
}

std::vector<PartResult> monte_carlo_linear(const GaugingProcess& p, const LinearGauge& g,
                                           double s_th, std::size_t parts, std::uint64_t seed,
                                           unsigned threads) {
  std::vector<PartResult> out(parts);
  monte_carlo_linear(p, g, s_th, 0, out, seed, threads);
  return out;
}

void monte_carlo_linear(const GaugingProcess& p, const LinearGauge& g, double s_th,
                        std::size_t first, std::span<PartResult> out, std::uint64_t seed,
                        unsigned threads) {
  const std::size_t parts = out.size();
  // In chunks of parts (a part is short); part first + i has its own stream whatever thread (or
  // block of the caller's) machines it.
  if (g.filter != LinearGauge::Filter::FirstOrder) {
    const double h = filtered_step(p, g);
    constexpr std::size_t kChunk = 256;  // divides kLinearPartChunk
    core::parallel_for((parts + kChunk - 1) / kChunk,
                       [&](std::size_t c) {
                         FilteredNoise noise(p, g, h);  // one buffer per chunk
                         for (std::size_t i = c * kChunk; i < std::min(parts, (c + 1) * kChunk);
                              ++i) {
                           std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + first + i);
                           out[i] = one_filtered_part(p, g, s_th, noise, h, rng);
                         }
                       },
                       threads);
    return;
  }
  // Step: a twentieth of the shorter of the filter lag and the noise correlation time; the
  // transition is exact, the step only sets how finely the crossing is interpolated.
  const double corr =
      std::min(g.filter_s, p.noise_beta_per_s > 0.0 ? 1.0 / p.noise_beta_per_s : g.filter_s);
  const double h = corr / 20.0;
  const Transition tr = transition(p, g, h);
  const Stationary st = stationary(tr);
  constexpr std::size_t kChunk = kLinearPartChunk;
  core::parallel_for(
      (parts + kChunk - 1) / kChunk,
      [&](std::size_t c) {
        for (std::size_t i = c * kChunk; i < std::min(parts, (c + 1) * kChunk); ++i) {
          std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + first + i);  // one stream per part
          out[i] = one_linear_part(p, g, s_th, tr, st, h, rng);
        }
      },
      threads);
}

FirstPassageBias first_passage_bias(LinearParts& parts, double target_m, double gain_V_per_m) {
  const auto each = [&](auto&& f) {  // f(e, y) over the parts the calibration uses
    parts.for_each([&](std::size_t, const PartResult& r) {
      if (!r.backstop && std::isfinite(r.noise_at_nominal_V))
        f(r.finished_m - target_m, r.noise_at_nominal_V / gain_V_per_m);
    });
  };
  std::size_t n = 0;
  double mean_e = 0.0, mean_y = 0.0, var_y = 0.0, cov = 0.0, res = 0.0;
  each([&](double e, double y) {
    mean_e += e;
    mean_y += y;
    ++n;
  });
  mean_e /= static_cast<double>(n);
  mean_y /= static_cast<double>(n);
  each([&](double e, double y) {
    var_y += (y - mean_y) * (y - mean_y);
    cov += (e - mean_e) * (y - mean_y);
  });
  const double sigma_y = n > 1 ? std::sqrt(var_y / static_cast<double>(n - 1)) : 0.0;
  cov /= static_cast<double>(std::max<std::size_t>(n, 2) - 1);
  const double c = sigma_y > 0.0 ? cov / (sigma_y * sigma_y) : 0.0;
  FirstPassageBias b;
  b.bias_m = mean_e - c * mean_y;
  each([&](double e, double y) {
    const double v = e - c * y - b.bias_m;
    res += v * v;
  });
  b.standard_error_m = std::sqrt(res / static_cast<double>(std::max<std::size_t>(n, 2) - 1) /
                                 static_cast<double>(std::max<std::size_t>(n, 1)));
  return b;
}

std::vector<double> filter_noise_samples(const GaugingProcess& p, const LinearGauge& g,
                                         std::size_t n, double spacing_s, std::uint64_t seed) {
  if (g.filter != LinearGauge::Filter::FirstOrder) {
    const double h = filtered_step(p, g);
    FilteredNoise noise(p, g, h);
    std::mt19937_64 rng(seed);
    noise.start(rng);
    const auto every = std::max<std::size_t>(1, static_cast<std::size_t>(spacing_s / h));
    std::vector<double> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      double e = 0.0;
      for (std::size_t k = 0; k < every; ++k) e = noise.step(rng);
      out.push_back(e);
    }
    return out;
  }
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

namespace {
// The size under the removal: x = x0 − rate·(t − t0) from t0 on, one segment a step of the cycle
// (each step's command sets its rate when it operates).
class RemovalSegments {
 public:
  struct Segment {
    double t0, x0, rate;
  };
  RemovalSegments(double x0, double rate) { seg_[0] = {0.0, x0, rate}; }
  [[nodiscard]] const Segment& at(double t) const {
    std::size_t i = n_ - 1;
    while (i > 0 && seg_[i].t0 > t) --i;
    return seg_[i];
  }
  [[nodiscard]] double x(double t) const {
    const Segment& s = at(t);
    return s.x0 - s.rate * (t - s.t0);
  }
  [[nodiscard]] bool full() const { return n_ >= seg_.size(); }
  void add(double t0, double x0, double rate) { seg_[n_++] = {t0, x0, rate}; }

 private:
  std::array<Segment, control::GaugeMachine::kMaxSteps + 1> seg_{};
  std::size_t n_ = 1;
};
}  // namespace

PartResult machine_part_full(const GaugingProcess& p, const sensors::VibroContactGauge::Params& gp,
                             double dt, double s_th, std::uint64_t seed, sim::Recorder* rec,
                             std::size_t record_every, double max_time_s) {
  sensors::VibroContactGauge g;
  g.configure(gp, dt);
  // The machine side: the same object the LinuxCNC component runs. A threshold the free probe
  // cannot reach is the study's own case (gauge.force_threshold): the backstop ends the cut.
  control::GaugeMachine machine;
  machine.configure(machine_params(p, g, s_th));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  dynamics::OrnsteinUhlenbeck xi;  // the size's disturbance ξ, as the LinuxCNC plant's
  xi.configure(p.noise_variance_m2, p.noise_beta_per_s, dt);
  xi.start(n01(rng));
  const double a = p.removal_m_per_s;
  // The removal in segments, one a step of the cycle (one, the size step's, without a cycle).
  RemovalSegments seg(p.allowance_m,
                      a * p.cycle.rate_factor_of(p.cycle.before.empty()
                                                     ? control::GaugeMachine::Command::Size
                                                     : control::GaugeMachine::Command::Rough));
  const auto seg_at = [&](double t) -> const RemovalSegments::Segment& { return seg.at(t); };
  const auto x_at = [&](double t) { return seg.x(t); };
  const auto& ir = p.interruption;
  // Each part meets the interruptions at its own angle.
  const double theta0 =
      ir.any() ? std::uniform_real_distribution<double>(0.0, 2.0 * std::numbers::pi)(rng) : 0.0;
  const double omega = 2.0 * std::numbers::pi * ir.spindle_rpm / 60.0;
  const double t_expected = a > 0.0 ? (p.allowance_m - p.target_m) / a : 1.0;
  const double t_max =
      max_time_s > 0.0 ? max_time_s : 2.0 * t_expected + 10.0 * gp.filter_time_constant_s + 1.0;
  PartResult r;
  r.trip_s = r.stop_s = std::numeric_limits<double>::quiet_NaN();
  double stop = std::numeric_limits<double>::infinity();
  double x = p.allowance_m;
  const bool limited = a > 0.0 && std::isfinite(p.backstop_m);
  std::int32_t operated = 0;  // the cycle's steps scheduled into segments
  // The filter starts from its free reading; let it see the first contact (no skipped physics).
  for (std::size_t k = 0;; ++k) {
    const double t = g.time_s();
    if (t >= t_max) break;
    if ((k & 0x3fff) == 0) io::ProgressScope::poll();  // a caller may stop a long part
    x = x_at(std::min(t, stop));
    const double xi_now = xi.step(n01(rng));
    const double theta = theta0 + omega * t;
    control::GaugeMachine::Input in;
    in.generator_V = g.step_generator(x + xi_now - (ir.any() ? ir.depth_at(theta) : 0.0));
    in.gate = ir.gate && ir.under(theta);
    // Where the size is at the end of this sample (the backstop's limit position on x).
    in.position_m = limited ? x_at(std::min(t + dt, stop)) : std::numeric_limits<double>::infinity();
    machine.update(in);
    const auto& out = machine.output();
    // A crossing: its command operates t_r later — the next step's rate from then, or the end.
    if (out.tripped) {
      const double at = out.trip_time_s + p.relay_response_s;
      const auto last = static_cast<std::int32_t>(p.cycle.before.size());
      if (out.tripped_steps > last) {
        if (std::isnan(r.trip_s)) {
          r.trip_s = out.trip_time_s;
          if (at < stop) {
            stop = at;
            r.stop_s = stop;
          }
        }
      } else if (out.tripped_steps > operated && !seg.full() && at < stop) {
        const auto c = p.cycle.before[static_cast<std::size_t>(out.tripped_steps - 1)].command;
        const double x0 = x_at(at);
        seg.add(at, x0, a * p.cycle.rate_factor_of(c));
        for (auto j = operated; j < out.tripped_steps; ++j)
          r.step_at_m[static_cast<std::size_t>(j)] = x0;
      }
      operated = out.tripped_steps;
    }
    if (out.backstop && !r.backstop) {  // x reaches the limit position first
      const auto& s = seg_at(g.time_s());
      stop = s.t0 + (s.x0 - p.backstop_m) / s.rate;
      r.stop_s = stop;
      r.backstop = true;
    }
    if (rec && k % record_every == 0) {
      const std::array<double, 5> row{t, x * 1e6, (x + xi_now) * 1e6, out.signal_V,
                                      g.probe_position_m() * 1e6};
      rec->push_row(row);
    }
    if (t > stop + 5.0 * gp.filter_time_constant_s) break;
  }
  r.finished_m = std::isfinite(stop) ? x_at(stop) : x;
  return r;
}

SignalLevel full_model_signal(const sensors::VibroContactGauge::Params& gp, double dt, double x,
                              double settle_s, double average_s) {
  const auto l = sensors::VibroContactGauge::settled_signal(gp, dt, x, settle_s, average_s);
  return {l.mean_V, l.ripple_V};
}

}  // namespace lathectl::systems::d_gauging
