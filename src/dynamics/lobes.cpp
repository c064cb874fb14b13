// The chatter model's frequency-domain lobes and their envelope (semi-discretization and the
// time domain: lobes_sd.cpp).
#include "lathectl/dynamics/lobes.hpp"

#include "lathectl/dynamics/frf.hpp"
#include "lobes_check.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace lathectl::dynamics {

namespace detail {

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

}  // namespace detail

using detail::check;

namespace {
constexpr double kPi = std::numbers::pi;

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

}  // namespace lathectl::dynamics
