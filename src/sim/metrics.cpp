#include "lathectl/sim/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lathectl::sim {

MovingAverage::MovingAverage(std::size_t window) : ring_(std::max<std::size_t>(window, 1), 0.0) {}

double MovingAverage::push(double x) noexcept {
  const std::size_t w = ring_.size(), i = n_++;
  acc_ += x;
  if (i >= w) acc_ -= ring_[i % w];  // x[i − w]
  ring_[i % w] = x;
  return acc_ / static_cast<double>(std::min(i + 1, w));
}

std::vector<double> moving_average(std::span<const double> x, std::size_t window) {
  MovingAverage avg(window);
  std::vector<double> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = avg.push(x[i]);
  return out;
}

double mean_between(std::span<const double> t, std::span<const double> x, double t0, double t1) {
  MeanBetween m{t0, t1};
  for (std::size_t i = 0; i < t.size(); ++i) m.push(t[i], x[i]);
  return m.value();
}

AlarmOnsets::AlarmOnsets(const std::vector<sensors::SensorFault>& faults) {
  for (const auto& f : faults) first_fault_ = std::min(first_fault_, f.at_s);
}

void AlarmOnsets::push(double t, double alarm, double reason) {
  const bool on = alarm > 0.5;
  const bool was = was_;
  was_ = on;
  if (!on || was) return;
  out_.push_back({t, static_cast<int>(reason)});
  if (std::isnan(first_delay_s_) && t >= first_fault_) first_delay_s_ = t - first_fault_;
}

std::vector<AlarmEvent> alarm_onsets(std::span<const double> t, std::span<const double> alarm,
                                     std::span<const double> reason,
                                     const std::vector<sensors::SensorFault>& faults,
                                     double& first_delay_s) {
  AlarmOnsets onsets(faults);
  for (std::size_t i = 0; i < t.size(); ++i) onsets.push(t[i], alarm[i], reason[i]);
  first_delay_s = onsets.first_delay_s();
  return onsets.events();
}

}  // namespace lathectl::sim
