#include "lathectl/dynamics/frf.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace lathectl::dynamics {

void check_frf(const Frf& frf) {
  const auto& f = frf.frequency_Hz;
  if (f.size() < 2 || f.size() != frf.receptance_m_per_N.size())
    throw std::invalid_argument("FRF: at least two samples, one value per frequency");
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!(f[i] > 0.0) || !std::isfinite(f[i]) || (i > 0 && !(f[i] > f[i - 1])))
      throw std::invalid_argument("FRF: frequencies must be finite, > 0 and strictly ascending");
    const auto h = frf.receptance_m_per_N[i];
    if (!std::isfinite(h.real()) || !std::isfinite(h.imag()))
      throw std::invalid_argument("FRF: values must be finite");
  }
}

std::complex<double> frf_at(const Frf& frf, double f_Hz) noexcept {
  const auto& f = frf.frequency_Hz;
  if (f.empty() || !(f_Hz >= f.front() && f_Hz <= f.back())) return 0.0;
  const auto it = std::upper_bound(f.begin(), f.end(), f_Hz);
  if (it == f.end()) return frf.receptance_m_per_N.back();
  const auto i = static_cast<std::size_t>(it - f.begin());  // f[i-1] ≤ f_Hz < f[i], i ≥ 1
  const double t = (f_Hz - f[i - 1]) / (f[i] - f[i - 1]);
  if (frf.baseline.empty())
    return frf.receptance_m_per_N[i - 1] +
           t * (frf.receptance_m_per_N[i] - frf.receptance_m_per_N[i - 1]);
  const auto r0 = frf.receptance_m_per_N[i - 1] - modal_frf(frf.baseline, f[i - 1]);
  const auto r1 = frf.receptance_m_per_N[i] - modal_frf(frf.baseline, f[i]);
  return modal_frf(frf.baseline, f_Hz) + r0 + t * (r1 - r0);
}

std::complex<double> modal_frf(const std::vector<Mode>& modes, double f_Hz) noexcept {
  std::complex<double> h = 0.0;
  for (const auto& m : modes) {
    const double r = f_Hz / m.natural_frequency_Hz;
    const double c = std::cos(m.angle_rad);
    h += c * c /
         (m.stiffness_N_per_m * std::complex<double>(1.0 - r * r, 2.0 * m.damping_ratio * r));
  }
  return h;
}

namespace {

// The window's sums for the least squares Σ c_p·x^p, x = (f − f_i)/hw, about an anchor a near
// f_i: Σ u^k, Σ u^k·Re y, Σ u^k·Im y with u = (f − a)/hw, kept as the window slides (a sample
// added on the right, one dropped on the left: O(1) per step) and moved to x by the binomial
// shift x = u − d, d = (f_i − a)/hw. The anchor moves to f_i, and the sums are taken afresh,
// once |d| passes ½ (every quarter window or so: O(n) in all), so that |u| ≤ 1.5 and the shift
// and the running sums lose no more than a few bits.
struct WindowMoments {
  static constexpr int kMax = 13;  // 2·6 + 1
  double anchor = 0.0;
  std::size_t lo = 0, hi = 0;      // the window summed, [lo, hi)
  bool valid = false;
  double m[kMax] = {}, re[kMax] = {}, im[kMax] = {};

  void add(const Frf& in, std::size_t j, double hw, int terms, double sign) {
    const double u = (in.frequency_Hz[j] - anchor) / hw;
    const auto y = in.receptance_m_per_N[j];
    double up = sign;
    for (int k = 0; k < 2 * terms - 1; ++k, up *= u) {
      m[k] += up;
      if (k < terms) {
        re[k] += up * y.real();
        im[k] += up * y.imag();
      }
    }
  }
  void move_to(const Frf& in, std::size_t i, std::size_t l, std::size_t h, double hw, int terms) {
    if (!valid || std::abs(in.frequency_Hz[i] - anchor) > 0.5 * hw || l >= hi) {
      *this = WindowMoments{};
      anchor = in.frequency_Hz[i];
      lo = hi = l;
      valid = true;
    }
    for (; hi < h; ++hi) add(in, hi, hw, terms, 1.0);
    for (; lo < l; ++lo) add(in, lo, hw, terms, -1.0);
  }
};

// The normal equations at f_i from the moments: Σ x^k = Σ_m C(k,m)·(−d)^(k−m)·Σ u^m.
void shifted_normal_equations(const WindowMoments& w, double d, int terms, Eigen::MatrixXd& A,
                              Eigen::VectorXd& br, Eigen::VectorXd& bi) {
  double binom[WindowMoments::kMax][WindowMoments::kMax] = {};
  double nd[WindowMoments::kMax];  // (−d)^k
  nd[0] = 1.0;
  for (int k = 1; k < WindowMoments::kMax; ++k) nd[k] = nd[k - 1] * -d;
  double sx[WindowMoments::kMax] = {};
  for (int k = 0; k < 2 * terms - 1; ++k) {
    binom[k][0] = binom[k][k] = 1.0;
    for (int j = 1; j < k; ++j) binom[k][j] = binom[k - 1][j - 1] + binom[k - 1][j];
    for (int j = 0; j <= k; ++j) sx[k] += binom[k][j] * nd[k - j] * w.m[j];
  }
  for (int p = 0; p < terms; ++p) {
    br(p) = bi(p) = 0.0;
    for (int j = 0; j <= p; ++j) {
      br(p) += binom[p][j] * nd[p - j] * w.re[j];
      bi(p) += binom[p][j] * nd[p - j] * w.im[j];
    }
    for (int q = 0; q < terms; ++q) A(p, q) = sx[p + q];
  }
}

}  // namespace

Frf smooth_frf(const Frf& in, double hw, int order) {
  check_frf(in);
  if (!(hw > 0.0)) return in;
  if (order < 0 || order > 6) throw std::invalid_argument("FRF smoothing: order 0 to 6");
  Frf out = in;
  const auto& f = in.frequency_Hz;
  const std::size_t n = f.size();
  const auto terms = static_cast<Eigen::Index>(order + 1);
  std::size_t lo = 0, hi = 0;  // window [lo, hi)
  Eigen::MatrixXd A(terms, terms);
  Eigen::VectorXd br(terms), bi(terms), phi(terms);
  WindowMoments moments;
  for (std::size_t i = 0; i < n; ++i) {
    while (f[lo] < f[i] - hw) ++lo;
    while (hi < n && f[hi] <= f[i] + hw) ++hi;
    if (hi - lo <= static_cast<std::size_t>(order + 1)) continue;  // the polynomial would be the data
    if (hi - lo > kSmoothingDirectSamples) {
      moments.move_to(in, i, lo, hi, hw, static_cast<int>(terms));
      shifted_normal_equations(moments, (f[i] - moments.anchor) / hw, static_cast<int>(terms), A,
                               br, bi);
    } else {
      // Least squares Σ c_p·x^p, x = (f − f_i)/hw, summed sample by sample; the value is c_0.
      A.setZero();
      br.setZero();
      bi.setZero();
      for (std::size_t j = lo; j < hi; ++j) {
        const double x = (f[j] - f[i]) / hw;
        double xp = 1.0;
        for (Eigen::Index p = 0; p < terms; ++p, xp *= x) phi(p) = xp;
        A.noalias() += phi * phi.transpose();
        br += phi * in.receptance_m_per_N[j].real();
        bi += phi * in.receptance_m_per_N[j].imag();
      }
    }
    const auto ldlt = A.ldlt();
    out.receptance_m_per_N[i] = {ldlt.solve(br)(0), ldlt.solve(bi)(0)};
  }
  return out;
}

namespace {

// Parameters p = (ln f, ln ζ, ln k) per mode.
std::vector<Mode> modes_of(const Eigen::VectorXd& p) {
  std::vector<Mode> m(static_cast<std::size_t>(p.size() / 3));
  for (std::size_t i = 0; i < m.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(3 * i);
    m[i].natural_frequency_Hz = std::exp(p(k));
    m[i].damping_ratio = std::exp(p(k + 1));
    m[i].stiffness_N_per_m = std::exp(p(k + 2));
    m[i].angle_rad = 0.0;
  }
  return m;
}

// [Re; Im] of (Ĥ − H)/scale at every sample.
void residual(const Frf& frf, const Eigen::VectorXd& p, double scale, Eigen::VectorXd& r) {
  const auto modes = modes_of(p);
  const auto n = static_cast<Eigen::Index>(frf.frequency_Hz.size());
  r.resize(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto d = (modal_frf(modes, frf.frequency_Hz[k]) - frf.receptance_m_per_N[k]) / scale;
    r(i) = d.real();
    r(n + i) = d.imag();
  }
}

// Levenberg–Marquardt (Marquardt's diagonal scaling), forward-difference Jacobian.
void refine(const Frf& frf, Eigen::VectorXd& p, double scale, int& iterations) {
  Eigen::VectorXd r, r_try, r_d;
  residual(frf, p, scale, r);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  const Eigen::Index np = p.size();
  Eigen::MatrixXd J(r.size(), np);
  for (int it = 0; it < 100; ++it) {
    ++iterations;
    for (Eigen::Index c = 0; c < np; ++c) {
      Eigen::VectorXd q = p;
      q(c) += 1e-6;
      residual(frf, q, scale, r_d);
      J.col(c) = (r_d - r) / 1e-6;
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * JtJ.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd step = A.ldlt().solve(-g);
      const Eigen::VectorXd q = p + step;
      residual(frf, q, scale, r_try);
      const double c_try = r_try.squaredNorm();
      if (std::isfinite(c_try) && c_try < cost) {
        const double gain = (cost - c_try) / cost;
        p = q;
        r = r_try;
        cost = c_try;
        lambda = std::max(lambda / 10.0, 1e-12);
        improved = true;
        if (gain < 1e-10) return;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) return;
  }
}

double relative_residual(const Frf& frf, const std::vector<Mode>& modes) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < frf.frequency_Hz.size(); ++i) {
    num += std::norm(modal_frf(modes, frf.frequency_Hz[i]) - frf.receptance_m_per_N[i]);
    den += std::norm(frf.receptance_m_per_N[i]);
  }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace

FrfFit fit_modes(const Frf& frf, int max_modes) {
  check_frf(frf);
  const auto& f = frf.frequency_Hz;
  const std::size_t n = f.size();
  double scale = 0.0;
  for (const auto& h : frf.receptance_m_per_N) scale = std::max(scale, std::abs(h));
  if (!(scale > 0.0)) throw std::invalid_argument("FRF: no response to fit (all zero)");
  FrfFit best;
  best.residual = 1.0;  // no mode: Ĥ = 0
  Eigen::VectorXd p(0);
  for (int m = 0; m < max_modes; ++m) {
    // The largest peak of what the modes so far leave unexplained.
    const auto modes = modes_of(p);
    std::vector<double> mag(n);
    for (std::size_t i = 0; i < n; ++i)
      mag[i] = std::abs(frf.receptance_m_per_N[i] - modal_frf(modes, f[i]));
    const auto ip = static_cast<std::size_t>(std::max_element(mag.begin(), mag.end()) - mag.begin());
    const double peak = mag[ip], half = peak / std::sqrt(2.0);
    // Half-power crossings, linearly interpolated; one side doubled when the other leaves the band.
    std::size_t a = ip, b = ip;
    while (a > 0 && mag[a] >= half) --a;
    while (b + 1 < n && mag[b] >= half) ++b;
    auto cross = [&](std::size_t i, std::size_t j) {  // mag[i] < half ≤ mag[j]
      return f[i] + (half - mag[i]) / (mag[j] - mag[i]) * (f[j] - f[i]);
    };
    const bool left = mag[a] < half, right = mag[b] < half;
    const double fl = left ? cross(a, a + 1) : f[ip], fr = right ? cross(b, b - 1) : f[ip];
    double band = left && right ? fr - fl : 2.0 * std::max(fr - f[ip], f[ip] - fl);
    if (!(band > 0.0)) band = 2.0 * (f[std::min(ip + 1, n - 1)] - f[ip > 0 ? ip - 1 : 0]);
    const double zeta = std::clamp(band / (2.0 * f[ip]), 1e-4, 0.5);
    const double k = 1.0 / (2.0 * zeta * peak);
    Eigen::VectorXd q(p.size() + 3);
    q << p, std::log(f[ip]), std::log(zeta), std::log(k);
    int iterations = 0;
    refine(frf, q, scale, iterations);
    const auto trial = modes_of(q);
    // A mode outside the measured band, or damped beyond any structure's, is the fit absorbing
    // what lies outside the band (a stiff mode above it looks like a constant compliance): not
    // a mode, and never one semi-discretization should resolve.
    const bool physical = std::all_of(trial.begin(), trial.end(), [&](const Mode& md) {
      return md.natural_frequency_Hz >= f.front() && md.natural_frequency_Hz <= f.back() &&
             md.damping_ratio <= 0.5 && std::isfinite(md.stiffness_N_per_m);
    });
    const double rho = relative_residual(frf, trial);
    if (!physical || !(rho < best.residual * (2.0 / 3.0))) break;  // noise, not a peak
    best.modes = trial;
    best.residual = rho;
    best.iterations += iterations;
    p = q;
  }
  if (best.modes.empty()) throw std::invalid_argument("FRF: no resonance peak could be fitted");
  std::sort(best.modes.begin(), best.modes.end(), [](const Mode& x, const Mode& y) {
    return x.natural_frequency_Hz < y.natural_frequency_Hz;
  });
  return best;
}

Frf smooth_against_fit(const Frf& frf, const FrfFit& fit, double hw, int order) {
  check_frf(frf);
  Frf residual = frf;
  residual.baseline.clear();
  for (std::size_t i = 0; i < frf.frequency_Hz.size(); ++i)
    residual.receptance_m_per_N[i] -= modal_frf(fit.modes, frf.frequency_Hz[i]);
  Frf out = smooth_frf(residual, hw, order);
  for (std::size_t i = 0; i < out.frequency_Hz.size(); ++i)
    out.receptance_m_per_N[i] += modal_frf(fit.modes, out.frequency_Hz[i]);
  out.baseline = fit.modes;
  return out;
}

double smoothing_half_window_Hz(const FrfFit& fit) noexcept {
  double hw = 0.0;
  for (const auto& m : fit.modes) {
    const double w = 3.0 * m.damping_ratio * m.natural_frequency_Hz;
    if (hw == 0.0 || w < hw) hw = w;
  }
  return hw;
}

double samples_per_bandwidth(const Frf& frf, const FrfFit& fit) {
  check_frf(frf);
  std::vector<double> df(frf.frequency_Hz.size() - 1);
  for (std::size_t i = 0; i < df.size(); ++i) df[i] = frf.frequency_Hz[i + 1] - frf.frequency_Hz[i];
  std::nth_element(df.begin(), df.begin() + static_cast<std::ptrdiff_t>(df.size() / 2), df.end());
  const double spacing = df[df.size() / 2];
  double band = std::numeric_limits<double>::infinity();
  for (const auto& m : fit.modes) band = std::min(band, 2.0 * m.damping_ratio * m.natural_frequency_Hz);
  return band / spacing;
}

Frf sum_frfs(const std::vector<Frf>& frfs) {
  if (frfs.empty()) throw std::invalid_argument("FRF: nothing to sum");
  double lo = 0.0, hi = 1e300;
  for (const auto& x : frfs) {
    check_frf(x);
    lo = std::max(lo, x.frequency_Hz.front());
    hi = std::min(hi, x.frequency_Hz.back());
  }
  Frf out;
  for (const double f : frfs.front().frequency_Hz) {
    if (f < lo || f > hi) continue;
    std::complex<double> h = 0.0;
    for (const auto& x : frfs) h += frf_at(x, f);
    out.frequency_Hz.push_back(f);
    out.receptance_m_per_N.push_back(h);
  }
  check_frf(out);
  return out;
}

}  // namespace lathectl::dynamics
