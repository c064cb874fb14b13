// The chatter model's semi-discretization (Insperger–Stépán: the map over one delay, its unstable
// roots, the stability chart, the limit depth by bisection) and its time-domain simulation; the
// frequency domain is in lobes.cpp.
#include "lathectl/dynamics/lobes.hpp"

#include "lathectl/core/parallel.hpp"
#include "lathectl/dynamics/frf.hpp"

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
#include <utility>
#include <unsupported/Eigen/MatrixFunctions>

#include "lobes_check.hpp"

namespace lathectl::dynamics {

using detail::check_modal;

namespace {
constexpr double kPi = std::numbers::pi;
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
struct SdStep {
  Eigen::MatrixXd P;               // d × d
  std::vector<Eigen::VectorXd> g;  // g[a]: weight of node σ_a = lo + a
  int lo = 0;                      // first node, −(order − 1)/2
};

void sd_step(const SdModel& s, double kb, double dt, int order, SdStep& st) {
  const Eigen::Index d = s.A.rows();
  st.lo = -((order - 1) / 2);
  const int n_nodes = order + 1;
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
  st.P = E.topLeftCorner(d, d);
  st.g.assign(static_cast<std::size_t>(n_nodes), Eigen::VectorXd::Zero(d));
  for (int a = 0; a < n_nodes; ++a) {  // Lagrange basis polynomial of node σ_a, as monomials
    std::vector<double> c{1.0};
    const int sa = st.lo + a;
    for (int b = 0; b < n_nodes; ++b) {
      if (b == a) continue;
      const int sb = st.lo + b;
      std::vector<double> next(c.size() + 1, 0.0);
      for (std::size_t p = 0; p < c.size(); ++p) {
        next[p + 1] += c[p] / (sa - sb);
        next[p] -= c[p] * sb / (sa - sb);
      }
      c = next;
    }
    for (std::size_t p = 0; p < c.size(); ++p) st.g[static_cast<std::size_t>(a)] += c[p] * J[p];
  }
}

// The map z_{i+1} = D·z_i, z = [x_i; y_{i−1}; ...; y_{i−h}] (h = m − lo history points).
void sd_map(const SdModel& s, double kb, double dt, int m, int order, Eigen::MatrixXd& D) {
  SdStep st;
  sd_step(s, kb, dt, order, st);
  const Eigen::Index d = s.A.rows();
  const Eigen::Index h = m - st.lo;
  const Eigen::Index n = d + h;
  D.setZero(n, n);
  D.topLeftCorner(d, d) = st.P;
  for (std::size_t a = 0; a < st.g.size(); ++a) {
    const int sa = st.lo + static_cast<int>(a);
    D.block(0, d + m - sa - 1, d, 1) += st.g[a];  // y_{i−j} sits at d + j − 1, j = m − σ
  }
  D.block(d, 0, 1, d) = s.v.transpose();
  for (Eigen::Index k = 1; k < h; ++k) D(d + k, d + k - 1) = 1.0;
}

// The number of eigenvalues of the SD map outside the unit circle, without forming the map.
// An eigenvector of D carries the history y_{i−j} = vᵀx·μ^{−j}, so μ ≠ 0 is an eigenvalue iff
//   f(μ) = det(μI − P − G(μ)·vᵀ) = 0,  G(μ) = Σ_σ g_σ·μ^{σ−m},
// and μ^{m−lo}·f(μ) is D's characteristic polynomial (degree d + m − lo, the force being rank
// one: matrix determinant lemma). By the argument principle, with W the winding number of f
// around 0 along |μ| = 1 (its pole of order m − lo at 0 counted), the roots outside number
//   d − W.
// f(μ̄) = conj f(μ) (real coefficients): the upper half circle winds by π·W. f is sampled at
// 4·(m − lo + d) + 32 angles, and an interval is halved while its phase step exceeds π/4, so a
// root near the circle (a cell near the boundary) is resolved rather than stepped over. Cost
// O(m·d³) against the eigenvalue solve's O((d + m)³): 0.1 ms instead of 130 ms at m = 400.
struct CountWorkspace {
  Eigen::MatrixXcd M;
  Eigen::VectorXcd G;
  // The base grid's e^{jθ_k} and e^{jθ_k(lo − m)}, kept while m and the grid stay the same (every
  // depth of a speed, and the bisection, reuse them).
  int m = -1, lo = 0, samples = 0;
  std::vector<std::complex<double>> mu, pw;
};

// f(μ) at μ = e^{jθ}, given μ and μ^{lo−m}.
std::complex<double> char_value(const SdStep& st, const Eigen::VectorXd& v, std::complex<double> mu,
                                std::complex<double> pw, CountWorkspace& w) {
  const Eigen::Index d = st.P.rows();
  w.G.setZero(d);
  for (const auto& g : st.g) {  // G(μ) = Σ_σ g_σ·μ^{σ−m}
    w.G += pw * g;
    pw *= mu;
  }
  w.M = -st.P.cast<std::complex<double>>() - w.G * v.transpose();
  w.M.diagonal().array() += mu;
  // Determinant by Gaussian elimination with partial pivoting, in place (d is small).
  std::complex<double> det = 1.0;
  for (Eigen::Index c = 0; c < d; ++c) {
    Eigen::Index piv = c;
    for (Eigen::Index r = c + 1; r < d; ++r)
      if (std::abs(w.M(r, c)) > std::abs(w.M(piv, c))) piv = r;
    if (piv != c) {
      w.M.row(c).swap(w.M.row(piv));
      det = -det;
    }
    const std::complex<double> p = w.M(c, c);
    det *= p;
    if (p == 0.0) return 0.0;
    for (Eigen::Index r = c + 1; r < d; ++r) {
      const std::complex<double> f = w.M(r, c) / p;
      w.M.row(r).tail(d - c - 1) -= f * w.M.row(c).tail(d - c - 1);
    }
  }
  return det;
}

std::complex<double> char_value_at(const SdStep& st, const Eigen::VectorXd& v, int m, double theta,
                                   CountWorkspace& w) {
  return char_value(st, v, std::polar(1.0, theta), std::polar(1.0, theta * (st.lo - m)), w);
}

double phase_change(const SdStep& st, const Eigen::VectorXd& v, int m, double t0,
                    std::complex<double> f0, double t1, std::complex<double> f1, int depth,
                    CountWorkspace& w) {
  const double step = std::arg(f1 * std::conj(f0));
  if (std::abs(step) <= 0.25 * kPi || depth >= 48) return step;
  const double tm = 0.5 * (t0 + t1);
  const auto fm = char_value_at(st, v, m, tm, w);
  return phase_change(st, v, m, t0, f0, tm, fm, depth + 1, w) +
         phase_change(st, v, m, tm, fm, t1, f1, depth + 1, w);
}

int unstable_roots(const SdStep& st, const Eigen::VectorXd& v, int m, CountWorkspace& w) {
  const auto d = static_cast<int>(st.P.rows());
  const int samples = 4 * (m - st.lo + d) + 32;
  if (w.m != m || w.lo != st.lo || w.samples != samples) {
    w.m = m;
    w.lo = st.lo;
    w.samples = samples;
    w.mu.resize(static_cast<std::size_t>(samples) + 1);
    w.pw.resize(w.mu.size());
    for (int k = 0; k <= samples; ++k) {
      const double t = kPi * k / samples;
      w.mu[static_cast<std::size_t>(k)] = std::polar(1.0, t);
      w.pw[static_cast<std::size_t>(k)] = std::polar(1.0, t * (st.lo - m));
    }
  }
  double total = 0.0, t0 = 0.0;
  std::complex<double> f0 = char_value(st, v, w.mu[0], w.pw[0], w);
  for (int k = 1; k <= samples; ++k) {
    const double t1 = kPi * k / samples;
    const auto kk = static_cast<std::size_t>(k);
    const auto f1 = char_value(st, v, w.mu[kk], w.pw[kk], w);
    total += phase_change(st, v, m, t0, f0, t1, f1, 0, w);
    t0 = t1;
    f0 = f1;
  }
  return d - static_cast<int>(std::lround(total / kPi));
}

int sd_unstable_count(const SdModel& s, double kb, double dt, int m, int order) {
  thread_local SdStep st;
  thread_local CountWorkspace w;
  sd_step(s, kb, dt, order, st);
  return unstable_roots(st, s.v, m, w);
}

double spectral_radius(const Eigen::MatrixXd& D, Eigen::EigenSolver<Eigen::MatrixXd>& es) {
  es.compute(D, false);
  if (es.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return es.eigenvalues().cwiseAbs().maxCoeff();
}
}  // namespace

double spectral_radius_sd(const ChatterSystem& sys, double n, double b, int m, int order) {
  check_modal(sys);
  if (!(n > 0.0) || (order != 1 && order != 3 && order != 5) || m < 2 + (order - 1) / 2)
    throw std::invalid_argument("semi-discretization: speed > 0, order 1, 3 or 5, m ≥ 2 + order/2");
  Eigen::MatrixXd D;
  sd_map(sd_model(sys), sys.kf_N_per_m2 * b, 60.0 / n / m, m, order, D);
  Eigen::EigenSolver<Eigen::MatrixXd> es(D.rows());
  return spectral_radius(D, es);
}

int sd_unstable_roots(const ChatterSystem& sys, double n, double b, int m, int order) {
  check_modal(sys);
  if (!(n > 0.0) || (order != 1 && order != 3 && order != 5) || m < 2 + (order - 1) / 2)
    throw std::invalid_argument("semi-discretization: speed > 0, order 1, 3 or 5, m ≥ 2 + order/2");
  return sd_unstable_count(sd_model(sys), sys.kf_N_per_m2 * b, 60.0 / n / m, m, order);
}

int sd_steps_per_delay(const ChatterSystem& sys, double speed_rpm, double max_depth_m,
                       const SdChartOptions& o) {
  check_modal(sys);
  return sd_steps(sys, speed_rpm, max_depth_m, o);
}

SdChart sd_stability_chart(const ChatterSystem& sys, double min_rpm, double max_rpm, int n_speeds,
                           double max_depth_m, int n_depths, const SdChartOptions& o) {
  check_modal(sys);
  if (!(min_rpm > 0.0) || !(max_rpm > min_rpm) || n_speeds < 2 || n_depths < 2 ||
      !(max_depth_m > 0.0) || o.steps_per_period < 1 || o.min_steps < 3 ||
      (o.interpolation_order != 1 && o.interpolation_order != 3 && o.interpolation_order != 5) ||
      !(o.boundary_rel_tol > 0.0 && o.boundary_rel_tol < 0.1))
    throw std::invalid_argument(
        "SD chart: 0 < min < max speed, ≥ 2 speeds and depths, max depth > 0, ≥ 1 step per "
        "period, ≥ 3 steps per delay, interpolation order 1, 3 or 5, boundary tolerance in "
        "(0, 0.1)");
  SdChart c;
  const auto ns = static_cast<std::size_t>(n_speeds), nd = static_cast<std::size_t>(n_depths);
  c.speed_rpm.resize(ns);
  c.depth_m.resize(nd);
  c.steps.resize(ns);
  c.unstable_roots.assign(ns * nd, 0);
  c.boundary_depth_m.assign(ns, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < ns; ++i) {
    c.speed_rpm[i] =
        min_rpm + (max_rpm - min_rpm) * static_cast<double>(i) / static_cast<double>(ns - 1);
    c.steps[i] = sd_steps(sys, c.speed_rpm[i], max_depth_m, o);
  }
  for (std::size_t j = 0; j < nd; ++j)
    c.depth_m[j] = max_depth_m * static_cast<double>(j) / static_cast<double>(nd - 1);
  const SdModel model = sd_model(sys);
  // The cost per speed grows as m and m as 1/speed: the speeds ascend, so the slow ones are
  // handed out first and the cheap ones fill the gaps at the end.
  std::atomic<std::size_t> finished{0};
  core::parallel_for(
      ns,
      [&](std::size_t i) {
        const int m = c.steps[i];
        const double dt = 60.0 / c.speed_rpm[i] / m;
        auto count = [&](double b) {
          return sd_unstable_count(model, sys.kf_N_per_m2 * b, dt, m, o.interpolation_order);
        };
        std::size_t first = nd;  // the lowest unstable grid depth
        for (std::size_t j = 0; j < nd; ++j) {
          c.unstable_roots[i * nd + j] = count(c.depth_m[j]);
          if (c.unstable_roots[i * nd + j] > 0 && first == nd) first = j;
        }
        if (first == 0) {
          c.boundary_depth_m[i] = 0.0;
        } else if (first < nd) {  // the SD map's own boundary between the two grid depths
          double lo = c.depth_m[first - 1], hi = c.depth_m[first];
          // At most 64 halvings: with depths near the denormals (a stiffness of 1e-300 N/m) the
          // midpoint stops moving and the tolerance is never met (it hung).
          for (int it = 0; it < 64 && hi - lo > o.boundary_rel_tol * hi; ++it) {
            const double mid = 0.5 * (lo + hi);
            (count(mid) > 0 ? hi : lo) = mid;
          }
          c.boundary_depth_m[i] = 0.5 * (lo + hi);
        }
        const std::size_t k = ++finished;
        if (o.on_speed_done) o.on_speed_done(k, ns);
      },
      o.threads > 0 ? static_cast<unsigned>(o.threads) : 0u);
  return c;
}

double sd_limit_depth(const ChatterSystem& sys, double n, double b_hi, int m, double rel_tol,
                      int order) {
  check_modal(sys);
  if (!(n > 0.0) || (order != 1 && order != 3 && order != 5) || m < 2 + (order - 1) / 2)
    throw std::invalid_argument("semi-discretization: speed > 0, order 1, 3 or 5, m ≥ 2 + order/2");
  const SdModel model = sd_model(sys);
  const double dt = 60.0 / n / m;
  auto stable = [&](double b) {
    return sd_unstable_count(model, sys.kf_N_per_m2 * b, dt, m, order) == 0;
  };
  if (!(b_hi > 0.0) || !std::isfinite(b_hi) || !(rel_tol > 0.0))
    throw std::invalid_argument("semi-discretization: 0 < depth_hi < ∞, rel_tol > 0");
  double lo = 0.0, hi = b_hi;
  if (stable(hi)) return std::numeric_limits<double>::infinity();
  for (int it = 0; it < 64 && hi - lo > rel_tol * hi; ++it) {  // capped: see the chart's
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TimeDomainResult time_domain(const ChatterSystem& sys, double n, double b, double h0,
                             double duration, int steps_per_period) {
  check_modal(sys);
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
