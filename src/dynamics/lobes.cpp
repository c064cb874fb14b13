#include "lathectl/dynamics/lobes.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
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
    for (int N = 0; N < max_lobes; ++N) {
      const double n = 60.0 * w / (eps + 2.0 * kPi * N);
      if (n < min_rpm || n > max_rpm) continue;
      auto& lobe = r.lobes[static_cast<std::size_t>(N)];
      const LobePoint p{n, b, w / (2.0 * kPi)};
      lobe.points.push_back(p);
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

double spectral_radius_sd(const ChatterSystem& sys, double n, double b, int m) {
  check(sys);
  const auto M = static_cast<Eigen::Index>(sys.modes.size());
  const Eigen::Index d = 2 * M;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(d, d), B = Eigen::MatrixXd::Zero(d, d);
  for (Eigen::Index i = 0; i < M; ++i) {
    const auto& md = sys.modes[static_cast<std::size_t>(i)];
    const double wn = 2.0 * kPi * md.natural_frequency_Hz;
    const double mass = md.stiffness_N_per_m / (wn * wn);
    A(i, M + i) = 1.0;
    A(M + i, i) = -wn * wn;
    A(M + i, M + i) = -2.0 * md.damping_ratio * wn;
    for (Eigen::Index j = 0; j < M; ++j)  // force along the chip thickness from y = Σ c_j q_j
      B(M + i, j) = std::cos(md.angle_rad) *
                    std::cos(sys.modes[static_cast<std::size_t>(j)].angle_rad) / mass;
  }
  const double tau = 60.0 / n, dt = tau / m, kb = sys.kf_N_per_m2 * b;
  const Eigen::MatrixXd Ab = A - kb * B;  // ẋ = Ab·x + kb·B·x(t − τ)
  // exp of [[Ab, I, 0], [0, 0, I], [0, 0, 0]]·dt → e^{Ab dt}, Φ0 = ∫e^{As}ds, ∫e^{As}(dt − s)ds
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(3 * d, 3 * d);
  big.block(0, 0, d, d) = Ab * dt;
  big.block(0, d, d, d) = Eigen::MatrixXd::Identity(d, d) * dt;
  big.block(d, 2 * d, d, d) = Eigen::MatrixXd::Identity(d, d) * dt;
  const Eigen::MatrixXd E = big.exp();
  const Eigen::MatrixXd P0 = E.block(0, 0, d, d);
  const Eigen::MatrixXd Phi0 = E.block(0, d, d, d);                  // ∫0^dt e^{As} ds
  const Eigen::MatrixXd Phi1 = dt * Phi0 - E.block(0, 2 * d, d, d);  // ∫ e^{As}·s ds
  const Eigen::MatrixXd Rm = (Phi1 / dt) * (kb * B);                 // coefficient of x_{i−m}
  const Eigen::MatrixXd Rm1 = (Phi0 - Phi1 / dt) * (kb * B);         // coefficient of x_{i−m+1}
  const Eigen::Index n_z = d * (m + 1);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n_z, n_z);
  D.block(0, 0, d, d) = P0;
  D.block(0, d * (m - 1), d, d) += Rm1;
  D.block(0, d * m, d, d) += Rm;
  for (int k = 1; k <= m; ++k) D.block(d * k, d * (k - 1), d, d) = Eigen::MatrixXd::Identity(d, d);
  Eigen::EigenSolver<Eigen::MatrixXd> es(D, false);
  return es.eigenvalues().cwiseAbs().maxCoeff();
}

double sd_limit_depth(const ChatterSystem& sys, double n, double b_hi, int m, double rel_tol) {
  double lo = 0.0, hi = b_hi;
  if (spectral_radius_sd(sys, n, hi, m) < 1.0) return std::numeric_limits<double>::infinity();
  while (hi - lo > rel_tol * hi) {
    const double mid = 0.5 * (lo + hi);
    (spectral_radius_sd(sys, n, mid, m) < 1.0 ? lo : hi) = mid;
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
    double h = h0 - y + y_tau;
    double f = 0.0;
    if (h > 0.0) {
      f = sys.kf_N_per_m2 * b * h;
      surface[head] = y;
    } else {
      surface[head] = y_tau + h0;  // not cut: the old surface, one feed further on
      h = 0.0;
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
