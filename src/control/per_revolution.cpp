#include "lathectl/control/per_revolution.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::control {

void PerRevolutionMean::configure(double dt_s, double rpm_min) {
  if (!(dt_s > 0.0) || !(rpm_min > 0.0) || !std::isfinite(60.0 / rpm_min / dt_s))
    throw std::invalid_argument("per-revolution mean: need an interval > 0 and a speed > 0");
  dt_ = dt_s;
  rpm_min_ = rpm_min;
  m_ = static_cast<std::size_t>(std::max(1.0, std::ceil(60.0 / rpm_min / dt_s))) + 2;
  cum_.assign(m_, 0.0);
  if (n_ == 1) {  // the first sample, pushed before the interval was known
    cum_[1 % m_] = sum_;
    since_restart_ = 1;
  } else {
    since_restart_ = 0;  // (more than one: they are forgotten)
  }
}

double PerRevolutionMean::revolution_ago(double rpm) const noexcept {
  if (m_ == 0) return std::nan("");
  const double want = std::max(1.0, 60.0 / std::max(std::abs(rpm), rpm_min_) / dt_);
  const auto w = static_cast<std::size_t>(std::floor(want));
  const double frac = want - static_cast<double>(w);
  if (w + 2 > since_restart_) return std::nan("");
  // sample j is cum[j + 1] − cum[j]; the last one pushed is n_ − 1
  auto sample = [&](std::size_t j) { return cum_[(j + 1) % m_] - cum_[j % m_]; };
  const double a = sample(n_ - 1 - w), b = sample(n_ - 2 - w);
  return a + frac * (b - a);
}

double PerRevolutionMean::push(double x, double rpm) noexcept {
  sum_ += x;  // Σ x[0..n] = cum[n + 1], summed in the order of the record
  ++n_;
  if (m_ == 0) {  // the interval is not known yet: the sample's mean is itself
    since_restart_ = 1;
    value_ = x;
    return value_;
  }
  cum_[n_ % m_] = sum_;
  if (since_restart_ < m_ - 1) ++since_restart_;
  const double n_rpm = std::max(std::abs(rpm), rpm_min_);
  // One revolution exactly: its whole samples and the fraction of the one before. Rounded to
  // whole samples, a once-per-revolution swing (an eccentric blank's) was left in the mean by
  // up to half a sample's share of it: on a 20 ms record at 1300 rpm (2.3 samples a
  // revolution) a forged shaft's run read 17 % over its limit where it was 6 % (issue 47).
  const double want = std::max(1.0, 60.0 / n_rpm / dt_);
  double whole = std::floor(want);
  double frac = want - whole;
  if (frac > 1.0 - 1e-9) {  // a whole number of samples, as rounded
    whole += 1.0;
    frac = 0.0;
  } else if (frac < 1e-9) {
    frac = 0.0;
  }
  const auto w_want = static_cast<std::size_t>(whole);
  full_ = w_want + (frac > 0.0 ? 1 : 0) <= since_restart_;
  if (!full_ || frac == 0.0) {
    const auto w = std::clamp<std::size_t>(w_want, 1, since_restart_);
    value_ = (sum_ - cum_[(n_ - w) % m_]) / static_cast<double>(w);
    return value_;
  }
  const double before = cum_[(n_ - w_want) % m_];
  const double older = before - cum_[(n_ - w_want - 1) % m_];  // the sample before the window
  value_ = (sum_ - before + frac * older) / want;
  return value_;
}

double PerRevolutionPeak::push(double t_s, double x, double rpm, bool cutting) noexcept {
  const double mean = mean_.push(x, rpm);
  if (cutting && !was_cutting_) contact_t_ = t_s;
  was_cutting_ = cutting;
  counted_ = cutting && t_s - contact_t_ > 60.0 / std::max(std::abs(rpm), 1.0);
  if (counted_) peak_ = std::max(peak_, mean);
  return mean;
}

std::vector<double> per_revolution_mean(std::span<const double> x, std::span<const double> rpm,
                                        double dt_s) {
  PerRevolutionMean mean(dt_s);
  std::vector<double> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = mean.push(x[i], rpm[i]);
  return out;
}

PerRevolutionRecord per_revolution_peak(std::span<const double> t_s, std::span<const double> x,
                                        std::span<const double> rpm,
                                        std::span<const unsigned char> cutting, double dt_s) {
  PerRevolutionPeak peak;
  peak.configure(dt_s);
  PerRevolutionRecord out;
  out.mean.resize(x.size());
  out.counted.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    out.mean[i] = peak.push(t_s[i], x[i], rpm[i], cutting[i] != 0);
    out.counted[i] = peak.counted() ? 1 : 0;
  }
  out.peak = peak.peak();
  return out;
}

}  // namespace lathectl::control
