#include "lathectl/sim/per_revolution.hpp"

#include <algorithm>
#include <cmath>

namespace lathectl::sim {

void PerRevolutionMean::set_dt(double dt_s) {
  dt_ = dt_s;
  // The longest window: one revolution at 1 rpm; its cumulative sums plus the newest. The ring
  // grows to that size as samples come (a short record keeps no more than its own sums).
  m_ = static_cast<std::size_t>(std::max(1.0, std::round(60.0 / dt_s))) + 2;
  cum_.assign(1, 0.0);  // cum[0]
  // The sample pushed before the step was known (the first one): its sum.
  if (n_ >= 1) cum_.push_back(first_);
}

double PerRevolutionMean::push(double x, double rpm) {
  const std::size_t i = n_++;
  sum_ += x;  // Σ x[0..i] = cum[i + 1], summed in the same order as the whole-record form
  if (cum_.empty()) {  // step not known yet: only the first sample, whose mean is itself
    first_ = sum_;
    return sum_ / 1.0;
  }
  if (cum_.size() < m_)
    cum_.push_back(sum_);  // slot i + 1 (no wrap yet)
  else
    cum_[(i + 1) % m_] = sum_;
  const auto w = static_cast<std::size_t>(
      std::max(1.0, std::round(60.0 / std::max(rpm, 1.0) / dt_)));
  const std::size_t lo = i + 1 >= w ? i + 1 - w : 0;
  return (cum_[(i + 1) % m_] - cum_[lo % m_]) / static_cast<double>(i + 1 - lo);
}

std::vector<double> per_revolution_mean(std::span<const double> x, std::span<const double> rpm,
                                        double dt_s) {
  // Differences of the cumulative sum: the window may grow as well as shrink with the speed.
  PerRevolutionMean mean(dt_s);
  std::vector<double> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = mean.push(x[i], rpm[i]);
  return out;
}

}  // namespace lathectl::sim
