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

namespace lathectl::dynamics {

namespace {
constexpr double kPi = std::numbers::pi;

void check(const ChatterSystem& sys) {
  if (sys.modes.empty() && sys.frfs.empty())
    throw std::invalid_argument("chatter system: at least one mode or measured FRF");
  for (const auto& f : sys.frfs) check_frf(f);
  if (!(sys.kf_N_per_m2 > 0.0)) throw std::invalid_argument("chatter system: K_f must be > 0");
  if (!(sys.process_damping_C >= 0.0) || !std::isfinite(sys.process_damping_C))
    throw std::invalid_argument("chatter system: the process damping coefficient must be ≥ 0");
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
  for (const auto& f : sys.frfs) phi += frf_at(f, w / (2.0 * kPi));
  return phi;
}

// Semi-discretization and the time domain integrate modes: a measured FRF must be fitted first.
void check_modal(const ChatterSystem& sys) {
  check(sys);
  if (!sys.frfs.empty() || sys.modes.empty())
    throw std::invalid_argument(
        "chatter system: semi-discretization and the time domain need modes (fit the measured "
        "FRF: fit_modes)");
  if (sys.process_damping_C > 0.0)
    throw std::invalid_argument(
        "chatter system: process damping is modelled in the frequency domain only");
}
}  // namespace

namespace {
// The chatter frequencies both the solver and its counter walk: half the lowest mode's natural
// frequency to twice the highest's [rad/s], after the inputs are checked.
std::pair<double, double> frequency_band(const ChatterSystem& sys, double min_rpm, double max_rpm,
                                         int max_lobes, int points) {
  check(sys);
  if (!(min_rpm > 0.0) || !(max_rpm > min_rpm) || max_lobes < 1 || points < 1)
    throw std::invalid_argument("speed range: 0 < min < max; ≥ 1 lobe and frequency point");
  if (!sys.frfs.empty()) {  // the measured band, where every FRF is known
    double lo = 0.0, hi = 1e300;
    for (const auto& f : sys.frfs) {
      lo = std::max(lo, f.frequency_Hz.front());
      hi = std::min(hi, f.frequency_Hz.back());
    }
    if (!(hi > lo)) throw std::invalid_argument("chatter system: the measured FRFs' bands do not overlap");
    return {2.0 * kPi * lo, 2.0 * kPi * hi};
  }
  double f_lo = 1e300, f_hi = 0.0;
  for (const auto& m : sys.modes) {
    f_lo = std::min(f_lo, m.natural_frequency_Hz);
    f_hi = std::max(f_hi, m.natural_frequency_Hz);
  }
  return {2.0 * kPi * 0.5 * f_lo, 2.0 * kPi * 2.0 * f_hi};
}

// The lobe point of lobe N at chatter frequency w with process damping (ChatterSystem): the
// damping c at which the lobe equations with Φ_c = Φ/(1 + jω·c·Φ), b(c) = −1/(2K_f·Re Φ_c) and
// n(c) = 60ω/(ε(Φ_c) + 2πN), give back c = C·b(c)/n(c). H(c) = C·b(c)/n(c) − c is positive at
// c = 0; its root is bracketed by doubling c and found by the Illinois variant of regula falsi.
// False where none exists (Re Φ_c ≥ 0, or H stays positive: the damping a depth brings grows
// faster than the depth it allows, so no finite depth chatters at this frequency and lobe).
bool damped_point(const ChatterSystem& sys, double w, std::complex<double> phi, int N, double& b,
                  double& n) {
  auto at = [&](double c, double& bc, double& nc) {
    const auto pc = phi / (1.0 + std::complex<double>(0.0, w * c) * phi);
    if (!(pc.real() < 0.0)) return false;
    double eps = std::fmod(3.0 * kPi + 2.0 * std::atan2(pc.imag(), pc.real()), 2.0 * kPi);
    if (eps <= 0.0) eps += 2.0 * kPi;
    bc = -1.0 / (2.0 * sys.kf_N_per_m2 * pc.real());
    nc = 60.0 * w / (eps + 2.0 * kPi * N);
    return true;
  };
  double b0 = 0.0, n0 = 0.0;
  if (!at(0.0, b0, n0)) return false;
  double lo = 0.0, h_lo = sys.process_damping_C * b0 / n0;
  double hi = h_lo, h_hi = 0.0, bh = 0.0, nh = 0.0;
  for (int k = 0;; ++k) {  // bracket: H(hi) ≤ 0
    if (k == 60 || !at(hi, bh, nh)) return false;
    h_hi = sys.process_damping_C * bh / nh - hi;
    if (h_hi <= 0.0) break;
    lo = hi;
    h_lo = h_hi;
    hi *= 2.0;
  }
  int side = 0;
  double c = hi;
  b = bh;
  n = nh;
  for (int it = 0; it < 100 && std::abs(h_hi) > 0.0; ++it) {
    c = (lo * h_hi - hi * h_lo) / (h_hi - h_lo);
    double bc = 0.0, nc = 0.0;
    if (!at(c, bc, nc)) return false;
    b = bc;
    n = nc;
    const double h = sys.process_damping_C * bc / nc - c;
    if (std::abs(h) <= 1e-12 * c || hi - lo <= 1e-14 * hi) return true;
    if (h > 0.0) {
      lo = c;
      h_lo = h;
      if (side == 1) h_hi *= 0.5;
      side = 1;
    } else {
      hi = c;
      h_hi = h;
      if (side == -1) h_lo *= 0.5;
      side = -1;
    }
  }
  return true;
}
}  // namespace

double frequency_domain_point_count(const ChatterSystem& sys, double min_rpm, double max_rpm,
                                    int max_lobes, int points) {
  const auto [w0, w1] = frequency_band(sys, min_rpm, max_rpm, max_lobes, points);
  double count = 0.0;
  for (int k = 0; k <= points; ++k) {  // as frequency_domain_lobes: N with n in the range
    const double w = w0 + (w1 - w0) * k / points;
    const auto phi = oriented_frf(sys, w);
    if (!(phi.real() < 0.0)) continue;
    double eps = std::fmod(3.0 * kPi + 2.0 * std::atan2(phi.imag(), phi.real()), 2.0 * kPi);
    if (eps <= 0.0) eps += 2.0 * kPi;
    const double lo = std::max(0.0, std::ceil((60.0 * w / max_rpm - eps) / (2.0 * kPi)));
    const double hi = std::min(static_cast<double>(max_lobes - 1),
                               std::floor((60.0 * w / min_rpm - eps) / (2.0 * kPi)));
    if (hi >= lo) count += hi - lo + 1.0;
  }
  return count;
}

FrequencyDomainResult frequency_domain_lobes(const ChatterSystem& sys, double min_rpm,
                                             double max_rpm, int max_lobes, int points) {
  const auto [w0, w1] = frequency_band(sys, min_rpm, max_rpm, max_lobes, points);
  FrequencyDomainResult r;
  r.critical_depth_m = std::numeric_limits<double>::infinity();
  r.lobes.resize(static_cast<std::size_t>(max_lobes));
  for (int N = 0; N < max_lobes; ++N) {
    r.lobes[static_cast<std::size_t>(N)].N = N;
    r.lobes[static_cast<std::size_t>(N)].minimum.depth_m = std::numeric_limits<double>::infinity();
  }
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(max_lobes));  // k of each point
  const bool damped = sys.process_damping_C > 0.0;
  for (int k = 0; k <= points; ++k) {
    const double w = w0 + (w1 - w0) * k / points;
    const auto phi = oriented_frf(sys, w);
    if (!(phi.real() < 0.0)) continue;
    const double b = -1.0 / (2.0 * sys.kf_N_per_m2 * phi.real());
    if (!damped && b < r.critical_depth_m) {
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
      double n = 60.0 * w / (eps + 2.0 * kPi * N);
      double bn = b;
      if (damped && !damped_point(sys, w, phi, N, bn, n)) continue;
      if (n < min_rpm || n > max_rpm) continue;
      auto& lobe = r.lobes[static_cast<std::size_t>(N)];
      const LobePoint p{n, bn, w / (2.0 * kPi)};
      if (damped && bn < r.critical_depth_m) {
        r.critical_depth_m = bn;
        r.critical_chatter_Hz = w / (2.0 * kPi);
      }
      lobe.points.push_back(p);
      grid[static_cast<std::size_t>(N)].push_back(k);
      if (p.depth_m < lobe.minimum.depth_m) lobe.minimum = p;
    }
  }
  // Refine the absolute limit between grid points: golden section on b(ω) = −1/(2K_f Re Φ).
  // (With process damping the limit depends on the speed: the lowest lobe point in the range.)
  if (!damped && std::isfinite(r.critical_depth_m)) {
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
  index_envelope(r);
  return r;
}

namespace {
// Depth at speed n on segment (a, b), the speeds bracketing n, as the scan always computed it.
double on_segment(const LobePoint& a, const LobePoint& b, double n) {
  const double t = (n - a.speed_rpm) / (b.speed_rpm - a.speed_rpm);
  return a.depth_m + t * (b.depth_m - a.depth_m);
}
bool brackets(const LobePoint& a, const LobePoint& b, double n) {
  return !((n - a.speed_rpm) * (n - b.speed_rpm) > 0.0 || a.speed_rpm == b.speed_rpm);
}
}  // namespace

void index_envelope(FrequencyDomainResult& fd) {
  fd.envelope_runs.clear();
  for (std::size_t l = 0; l < fd.lobes.size(); ++l) {
    const auto& p = fd.lobes[l].points;
    std::size_t k = 1;
    while (k < p.size()) {
      if (p[k].speed_rpm == p[k - 1].speed_rpm) {  // skipped by the scan too
        ++k;
        continue;
      }
      EnvelopeRun r{l, k, k + 1, p[k].speed_rpm > p[k - 1].speed_rpm, 0.0, 0.0};
      while (r.last < p.size() && (p[r.last].speed_rpm > p[r.last - 1].speed_rpm) == r.ascending &&
             p[r.last].speed_rpm != p[r.last - 1].speed_rpm)
        ++r.last;
      r.lo_rpm = std::min(p[r.first - 1].speed_rpm, p[r.last - 1].speed_rpm);
      r.hi_rpm = std::max(p[r.first - 1].speed_rpm, p[r.last - 1].speed_rpm);
      fd.envelope_runs.push_back(r);
      k = r.last;
    }
  }
}

double envelope_depth(const FrequencyDomainResult& fd, double n) {
  double best = std::numeric_limits<double>::infinity();
  if (fd.envelope_runs.empty()) {  // no index: scan every segment
    for (const auto& lobe : fd.lobes)
      for (std::size_t i = 1; i < lobe.points.size(); ++i)
        if (brackets(lobe.points[i - 1], lobe.points[i], n))
          best = std::min(best, on_segment(lobe.points[i - 1], lobe.points[i], n));
    return best;
  }
  for (const auto& r : fd.envelope_runs) {
    if (!(n >= r.lo_rpm && n <= r.hi_rpm)) continue;
    const auto& p = fd.lobes[r.lobe].points;
    // The first segment whose far end (in the run's direction) reaches n; from there the
    // segments bracketing n follow one another (two where n is a shared point).
    std::size_t lo = r.first, hi = r.last;
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      const bool before = r.ascending ? p[mid].speed_rpm < n : p[mid].speed_rpm > n;
      (before ? lo : hi) = before ? mid + 1 : mid;
    }
    for (std::size_t k = lo; k < r.last && brackets(p[k - 1], p[k], n); ++k)
      best = std::min(best, on_segment(p[k - 1], p[k], n));
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
