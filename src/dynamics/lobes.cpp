#include "lathectl/dynamics/lobes.hpp"

#include "lathectl/sim/parallel.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <unsupported/Eigen/MatrixFunctions>

namespace lathectl::dynamics {

namespace {
constexpr double kPi = std::numbers::pi;

void check(const ChatterSystem& sys) {
  if (sys.modes.empty()) throw std::invalid_argument("chatter system: at least one mode");
  if (!(sys.kf_N_per_m2 > 0.0)) throw std::invalid_argument("chatter system: K_f must be > 0");
  for (const auto& m : sys.modes)
    if (!(m.stiffness_N_per_m > 0.0) || !(m.damping_ratio > 0.0) || !(m.natural_frequency_Hz > 0.0))
      throw std::invalid_argument("chatter system: each mode needs k > 0, ζ > 0, f_n > 0");
}

std::complex<double> oriented_frf(const ChatterSystem& sys, double w) {
  std::complex<double> phi = 0.0;
  for (const auto& m : sys.modes) {
    const double r = w / (2.0 * kPi * m.natural_frequency_Hz);
    const double c = std::cos(m.angle_rad);
    phi += c * c /
           (m.stiffness_N_per_m * std::complex<double>(1.0 - r * r, 2.0 * m.damping_ratio * r));
  }
  return phi;
}
}  // namespace

FrequencyDomainResult frequency_domain_lobes(const ChatterSystem& sys, double min_rpm,
                                             double max_rpm, int max_lobes, int points) {
  check(sys);
  if (!(min_rpm > 0.0) || !(max_rpm > min_rpm))
    throw std::invalid_argument("speed range: 0 < min < max");
  double f_lo = 1e300, f_hi = 0.0;
  for (const auto& m : sys.modes) {
    f_lo = std::min(f_lo, m.natural_frequency_Hz);
    f_hi = std::max(f_hi, m.natural_frequency_Hz);
  }
  FrequencyDomainResult r;
  r.critical_depth_m = std::numeric_limits<double>::infinity();
  r.lobes.resize(static_cast<std::size_t>(max_lobes));
  for (int N = 0; N < max_lobes; ++N) {
    r.lobes[static_cast<std::size_t>(N)].N = N;
    r.lobes[static_cast<std::size_t>(N)].minimum.depth_m = std::numeric_limits<double>::infinity();
  }
  const double w0 = 2.0 * kPi * 0.5 * f_lo, w1 = 2.0 * kPi * 2.0 * f_hi;
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(max_lobes));  // k of each point
  for (int k = 0; k <= points; ++k) {
    const double w = w0 + (w1 - w0) * k / points;
    const auto phi = oriented_frf(sys, w);
    if (!(phi.real() < 0.0)) continue;
    const double b = -1.0 / (2.0 * sys.kf_N_per_m2 * phi.real());
    if (b < r.critical_depth_m) {
      r.critical_depth_m = b;
      r.critical_chatter_Hz = w / (2.0 * kPi);
    }
    double eps = std::fmod(3.0 * kPi + 2.0 * std::atan2(phi.imag(), phi.real()), 2.0 * kPi);
    if (eps <= 0.0) eps += 2.0 * kPi;
    // Only the lobes whose speed 60ω/(ε + 2πN) can fall in the range (the rest is skipped
    // unvisited, so a large max_lobes costs nothing); the exact test below decides.
    const double n_lo = std::floor((60.0 * w / max_rpm - eps) / (2.0 * kPi)) - 1.0;
    const double n_hi = std::ceil((60.0 * w / min_rpm - eps) / (2.0 * kPi)) + 1.0;
    const int N0 = static_cast<int>(std::clamp(n_lo, 0.0, static_cast<double>(max_lobes)));
    const int N1 = static_cast<int>(std::clamp(n_hi, -1.0, static_cast<double>(max_lobes - 1)));
    for (int N = N0; N <= N1; ++N) {
      const double n = 60.0 * w / (eps + 2.0 * kPi * N);
      if (n < min_rpm || n > max_rpm) continue;
      auto& lobe = r.lobes[static_cast<std::size_t>(N)];
      const LobePoint p{n, b, w / (2.0 * kPi)};
      lobe.points.push_back(p);
      grid[static_cast<std::size_t>(N)].push_back(k);
      if (b < lobe.minimum.depth_m) lobe.minimum = p;
    }
  }
  // Refine the absolute limit between grid points: golden section on b(ω) = −1/(2K_f Re Φ).
  if (std::isfinite(r.critical_depth_m)) {
    const double dw = (w1 - w0) / points;
    double a = 2.0 * kPi * r.critical_chatter_Hz - dw, c = a + 2.0 * dw;
    auto depth = [&](double w) {
      const double re = oriented_frf(sys, w).real();
      return re < 0.0 ? -1.0 / (2.0 * sys.kf_N_per_m2 * re)
                      : std::numeric_limits<double>::infinity();
    };
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int k = 0; k < 80; ++k) {
      const double x1 = c - g * (c - a), x2 = a + g * (c - a);
      (depth(x1) < depth(x2) ? c : a) = depth(x1) < depth(x2) ? x2 : x1;
    }
    const double w = 0.5 * (a + c);
    if (depth(w) < r.critical_depth_m) {
      r.critical_depth_m = depth(w);
      r.critical_chatter_Hz = w / (2.0 * kPi);
    }
  }
  for (std::size_t N = 0; N < r.lobes.size(); ++N) {
    auto& lobe = r.lobes[N];
    const auto& ks = grid[N];
    std::size_t i = 0;
    while (i < lobe.points.size() && lobe.points[i].depth_m != lobe.minimum.depth_m) ++i;
    lobe.minimum_inside = i > 0 && i + 1 < lobe.points.size() && ks[i - 1] + 1 == ks[i] &&
                          ks[i + 1] == ks[i] + 1;
  }
  r.lobes.erase(std::remove_if(r.lobes.begin(), r.lobes.end(),
                               [](const Lobe& l) { return l.points.empty(); }),
                r.lobes.end());
  return r;
}

double envelope_depth(const FrequencyDomainResult& fd, double n) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& lobe : fd.lobes)
    for (std::size_t i = 1; i < lobe.points.size(); ++i) {
      const auto& a = lobe.points[i - 1];
      const auto& b = lobe.points[i];
      if ((n - a.speed_rpm) * (n - b.speed_rpm) > 0.0 || a.speed_rpm == b.speed_rpm) continue;
      const double t = (n - a.speed_rpm) / (b.speed_rpm - a.speed_rpm);
      best = std::min(best, a.depth_m + t * (b.depth_m - a.depth_m));
    }
  return best;
}

namespace {
// The chatter model in modal state x = [q; q̇] (d = 2M): ẋ = A·x + K_f·b·u·(y(t − τ) − y(t)),
// y = vᵀx the displacement along the chip thickness. The regenerative force acts through the
// rank-one u·vᵀ, so the history the map must carry is the scalar y, not the whole state: the SD
// map has dimension d + m instead of d·(m + 1) (Insperger & Stépán 2004 use the same reduction
// for their turning example).
struct SdModel {
  Eigen::MatrixXd A;
  Eigen::VectorXd u, v;
};

SdModel sd_model(const ChatterSystem& sys) {
  const auto M = static_cast<Eigen::Index>(sys.modes.size());
  const Eigen::Index d = 2 * M;
  SdModel s{Eigen::MatrixXd::Zero(d, d), Eigen::VectorXd::Zero(d), Eigen::VectorXd::Zero(d)};
  for (Eigen::Index i = 0; i < M; ++i) {
    const auto& md = sys.modes[static_cast<std::size_t>(i)];
    const double wn = 2.0 * kPi * md.natural_frequency_Hz;
    const double mass = md.stiffness_N_per_m / (wn * wn);
    s.A(i, M + i) = 1.0;
    s.A(M + i, i) = -wn * wn;
    s.A(M + i, M + i) = -2.0 * md.damping_ratio * wn;
    s.u(M + i) = std::cos(md.angle_rad) / mass;
    s.v(i) = std::cos(md.angle_rad);
  }
  return s;
}

// The frequency the steps must resolve: the highest among the modes that can chatter on the
// chart, i.e. whose own limit 2kζ(1+ζ)/(K_f·cos²θ) is below twice its top depth (a stiff high
// mode of a slender part would otherwise set m ten times larger for nothing).
double sd_reference_Hz(const ChatterSystem& sys, double max_depth_m) {
  double f_ref = 0.0, f_lowest_limit = 0.0, lowest_limit = std::numeric_limits<double>::infinity();
  for (const auto& md : sys.modes) {
    const double c2 = std::cos(md.angle_rad) * std::cos(md.angle_rad);
    const double limit = 2.0 * md.stiffness_N_per_m * md.damping_ratio * (1.0 + md.damping_ratio) /
                         (sys.kf_N_per_m2 * c2);
    if (limit <= 2.0 * max_depth_m) f_ref = std::max(f_ref, md.natural_frequency_Hz);
    if (limit < lowest_limit) lowest_limit = limit, f_lowest_limit = md.natural_frequency_Hz;
  }
  return f_ref > 0.0 ? f_ref : f_lowest_limit;
}

int sd_steps(const ChatterSystem& sys, double rpm, double max_depth_m, const SdChartOptions& o) {
  const double per_delay =
      std::ceil(60.0 / rpm * sd_reference_Hz(sys, max_depth_m) * o.steps_per_period);
  return static_cast<int>(std::clamp(per_delay, static_cast<double>(o.min_steps),
                                     static_cast<double>(std::max(o.min_steps, o.max_steps))));
}

// One SD step Δt = τ/m: the delayed y is a Lagrange polynomial through the history points
// y_{i−m+σ}, σ ∈ nodes (order 1: σ = 0, 1, the classic first-order SD; order 3: σ = −1..2,
// Insperger, Stépán & Turi, J. Sound Vib. 313 (2008) 334–341), the rest is integrated exactly:
//   x_{i+1} = P·x_i + Σ_σ g_σ·y_{i−m+σ},  P = e^{(A − kb·u·vᵀ)Δt}.
// The exponential of [[X·Δt, kb·u·Δt, 0..], [0, N·Δt]] (N the shift on a chain of p + 1
// integrators) holds P and K_k = ∫₀^Δt e^{X(Δt−s)}·kb·u·s^k/k! ds, k = 0..p, from which
// ∫ e^{X(Δt−s)}·kb·u·(s/Δt)^k ds = k!·K_k/Δt^k weigh the Lagrange basis' monomials.
// The map z_{i+1} = D·z_i, z = [x_i; y_{i−1}; ...; y_{i−h}] (h = m, or m + 1 for order 3).
void sd_map(const SdModel& s, double kb, double dt, int m, int order, Eigen::MatrixXd& D) {
  const Eigen::Index d = s.A.rows();
  const int lo = -((order - 1) / 2);
  const int n_nodes = order + 1;
  const Eigen::Index h = m - lo;  // history length
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(d + n_nodes, d + n_nodes);
  big.topLeftCorner(d, d) = (s.A - kb * s.u * s.v.transpose()) * dt;
  big.block(0, d, d, 1) = kb * dt * s.u;
  for (Eigen::Index k = 0; k + 1 < n_nodes; ++k) big(d + k, d + k + 1) = dt;
  const Eigen::MatrixXd E = big.exp();
  std::vector<Eigen::VectorXd> J;  // ∫ e^{X(Δt−s)}·kb·u·(s/Δt)^k ds
  double scale = 1.0;              // k!/Δt^k
  for (int k = 0; k < n_nodes; ++k) {
    if (k > 0) scale *= k / dt;
    J.push_back(scale * E.block(0, d + k, d, 1));
  }
  const Eigen::Index n = d + h;
  D.setZero(n, n);
  D.topLeftCorner(d, d) = E.topLeftCorner(d, d);
  for (int a = 0; a < n_nodes; ++a) {  // Lagrange basis polynomial of node σ_a, as monomials
    std::vector<double> c{1.0};
    const int sa = lo + a;
    for (int b = 0; b < n_nodes; ++b) {
      if (b == a) continue;
      const int sb = lo + b;
      std::vector<double> next(c.size() + 1, 0.0);
      for (std::size_t p = 0; p < c.size(); ++p) {
        next[p + 1] += c[p] / (sa - sb);
        next[p] -= c[p] * sb / (sa - sb);
      }
      c = next;
    }
    Eigen::VectorXd g = Eigen::VectorXd::Zero(d);
    for (std::size_t p = 0; p < c.size(); ++p) g += c[p] * J[p];
    D.block(0, d + m - sa - 1, d, 1) += g;  // y_{i−j} sits at d + j − 1, j = m − σ
  }
  D.block(d, 0, 1, d) = s.v.transpose();
  for (Eigen::Index k = 1; k < h; ++k) D(d + k, d + k - 1) = 1.0;
}

double spectral_radius(const Eigen::MatrixXd& D, Eigen::EigenSolver<Eigen::MatrixXd>& es) {
  es.compute(D, false);
  if (es.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return es.eigenvalues().cwiseAbs().maxCoeff();
}
}  // namespace

double spectral_radius_sd(const ChatterSystem& sys, double n, double b, int m, int order) {
  check(sys);
  if (!(n > 0.0) || (order != 1 && order != 3 && order != 5) || m < 2 + (order - 1) / 2)
    throw std::invalid_argument("semi-discretization: speed > 0, order 1, 3 or 5, m ≥ 2 + order/2");
  Eigen::MatrixXd D;
  sd_map(sd_model(sys), sys.kf_N_per_m2 * b, 60.0 / n / m, m, order, D);
  Eigen::EigenSolver<Eigen::MatrixXd> es(D.rows());
  return spectral_radius(D, es);
}

int sd_steps_per_delay(const ChatterSystem& sys, double speed_rpm, double max_depth_m,
                       const SdChartOptions& o) {
  check(sys);
  return sd_steps(sys, speed_rpm, max_depth_m, o);
}

SdChart sd_stability_chart(const ChatterSystem& sys, double min_rpm, double max_rpm, int n_speeds,
                           double max_depth_m, int n_depths, const SdChartOptions& o) {
  check(sys);
  if (!(min_rpm > 0.0) || !(max_rpm > min_rpm) || n_speeds < 2 || n_depths < 2 ||
      !(max_depth_m > 0.0) || o.steps_per_period < 1 || o.min_steps < 3 ||
      (o.interpolation_order != 1 && o.interpolation_order != 3 && o.interpolation_order != 5))
    throw std::invalid_argument(
        "SD chart: 0 < min < max speed, ≥ 2 speeds and depths, max depth > 0, ≥ 1 step per "
        "period, ≥ 3 steps per delay, interpolation order 1 or 3");
  SdChart c;
  const auto ns = static_cast<std::size_t>(n_speeds), nd = static_cast<std::size_t>(n_depths);
  c.speed_rpm.resize(ns);
  c.depth_m.resize(nd);
  c.steps.resize(ns);
  c.spectral_radius.assign(ns * nd, 0.0);
  c.boundary_depth_m.assign(ns, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < ns; ++i) {
    c.speed_rpm[i] =
        min_rpm + (max_rpm - min_rpm) * static_cast<double>(i) / static_cast<double>(ns - 1);
    c.steps[i] = sd_steps(sys, c.speed_rpm[i], max_depth_m, o);
  }
  for (std::size_t j = 0; j < nd; ++j)
    c.depth_m[j] = max_depth_m * static_cast<double>(j) / static_cast<double>(nd - 1);
  const SdModel model = sd_model(sys);
  // The cost per speed grows as (d + m)³ and m as 1/speed: the speeds ascend, so the slow ones
  // are handed out first and the cheap ones fill the gaps at the end.
  std::atomic<std::size_t> finished{0};
  sim::parallel_for(
      ns,
      [&](std::size_t i) {
        thread_local Eigen::MatrixXd D;  // workspaces kept per thread across speeds
        thread_local Eigen::EigenSolver<Eigen::MatrixXd> es;
        const int m = c.steps[i];
        const double dt = 60.0 / c.speed_rpm[i] / m;
        for (std::size_t j = 0; j < nd; ++j) {
          sd_map(model, sys.kf_N_per_m2 * c.depth_m[j], dt, m, o.interpolation_order, D);
          c.spectral_radius[i * nd + j] = spectral_radius(D, es);
        }
        const std::size_t k = ++finished;
        if (o.on_speed_done) o.on_speed_done(k, ns);
      },
      o.threads > 0 ? static_cast<unsigned>(o.threads) : 0u);
  for (std::size_t i = 0; i < ns; ++i) {
    for (std::size_t j = 0; j < nd; ++j) {
      const double r = c.radius(i, j);
      if (!std::isfinite(r))
        throw std::runtime_error("SD chart: the eigenvalue solver failed at " +
                                 std::to_string(c.speed_rpm[i]) + " rpm");
    }
    for (std::size_t j = 1; j < nd; ++j) {
      const double r0 = c.radius(i, j - 1), r1 = c.radius(i, j);
      if (r1 < 1.0) continue;
      const double t = r0 < 1.0 ? (1.0 - r0) / (r1 - r0) : 0.0;
      c.boundary_depth_m[i] = c.depth_m[j - 1] + t * (c.depth_m[j] - c.depth_m[j - 1]);
      break;
    }
  }
  return c;
}

double sd_limit_depth(const ChatterSystem& sys, double n, double b_hi, int m, double rel_tol,
                      int order) {
  double lo = 0.0, hi = b_hi;
  if (spectral_radius_sd(sys, n, hi, m, order) < 1.0)
    return std::numeric_limits<double>::infinity();
  while (hi - lo > rel_tol * hi) {
    const double mid = 0.5 * (lo + hi);
    (spectral_radius_sd(sys, n, mid, m, order) < 1.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TimeDomainResult time_domain(const ChatterSystem& sys, double n, double b, double h0,
                             double duration, int steps_per_period) {
  check(sys);
  double f_max = 0.0;
  for (const auto& m : sys.modes) f_max = std::max(f_max, m.natural_frequency_Hz);
  const double tau = 60.0 / n;
  // A whole number of steps per revolution, at least steps_per_period per vibration period.
  const auto per_rev = static_cast<std::size_t>(std::ceil(tau * f_max * steps_per_period));
  const double dt = tau / static_cast<double>(per_rev);
  const std::size_t M = sys.modes.size();
  std::vector<double> q(M, 0.0), v(M, 0.0), wn(M), mass(M), c(M);
  for (std::size_t i = 0; i < M; ++i) {
    wn[i] = 2.0 * kPi * sys.modes[i].natural_frequency_Hz;
    mass[i] = sys.modes[i].stiffness_N_per_m / (wn[i] * wn[i]);
    c[i] = std::cos(sys.modes[i].angle_rad);
  }
  // Static deflection under the nominal force, plus a small kick.
  double y_static = 0.0;
  for (std::size_t i = 0; i < M; ++i) {
    q[i] = c[i] * sys.kf_N_per_m2 * b * h0 / sys.modes[i].stiffness_N_per_m;
    y_static += c[i] * q[i];
  }
  v[0] += 1e-3 * h0 * wn[0];
  std::vector<double> surface(per_rev, y_static);  // surface left one revolution ago
  std::size_t head = 0;
  const auto steps = static_cast<std::size_t>(duration / dt);
  const std::size_t win = std::max<std::size_t>(
      per_rev * 5, static_cast<std::size_t>(0.05 * static_cast<double>(steps)));
  TimeDomainResult r;
  double early = 0.0, late = 0.0;
  for (std::size_t k = 0; k < steps; ++k) {
    double y = 0.0;
    for (std::size_t i = 0; i < M; ++i) y += c[i] * q[i];
    const double y_tau = surface[head];
    const double h = h0 - y + y_tau;
    double f = 0.0;
    if (h > 0.0) {
      f = sys.kf_N_per_m2 * b * h;
      surface[head] = y;
    } else {
      surface[head] = y_tau + h0;  // not cut: the old surface, one feed further on
    }
    head = (head + 1) % per_rev;
    for (std::size_t i = 0; i < M; ++i) {  // semi-implicit Euler per mode
      const double a = c[i] * f / mass[i] - 2.0 * sys.modes[i].damping_ratio * wn[i] * v[i] -
                       wn[i] * wn[i] * q[i];
      v[i] += a * dt;
      q[i] += v[i] * dt;
    }
    const double dev = std::abs(y - y_static);
    if (k >= per_rev && k < per_rev + win) early = std::max(early, dev);
    if (k + win >= steps) late = std::max(late, dev);
  }
  r.amplitude_early_m = early;
  r.amplitude_late_m = late;
  r.grew = late > early;
  return r;
}

}  // namespace lathectl::dynamics
