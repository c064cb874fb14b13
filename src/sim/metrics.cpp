#include "lathectl/sim/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lathectl::sim {

std::vector<double> moving_average(std::span<const double> x, std::size_t window) {
  std::vector<double> out(x.size());
  double acc = 0.0;
  window = std::max<std::size_t>(window, 1);
  for (std::size_t i = 0; i < x.size(); ++i) {
    acc += x[i];
    if (i >= window) acc -= x[i - window];
    out[i] = acc / static_cast<double>(std::min(i + 1, window));
  }
  return out;
}

double mean_between(std::span<const double> t, std::span<const double> x, double t0, double t1) {
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t0 && t[i] < t1) {
      s += x[i];
      ++n;
    }
  return n ? s / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

std::vector<AlarmEvent> alarm_onsets(std::span<const double> t, std::span<const double> alarm,
                                     std::span<const double> reason,
                                     const std::vector<SensorFault>& faults,
                                     double& first_delay_s) {
  double first_fault = std::numeric_limits<double>::infinity();
  for (const auto& f : faults) first_fault = std::min(first_fault, f.at_s);
  first_delay_s = std::numeric_limits<double>::quiet_NaN();
  std::vector<AlarmEvent> out;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool on = alarm[i] > 0.5;
    const bool was = i > 0 && alarm[i - 1] > 0.5;
    if (!on || was) continue;
    out.push_back({t[i], static_cast<int>(reason[i])});
    if (std::isnan(first_delay_s) && t[i] >= first_fault) first_delay_s = t[i] - first_fault;
  }
  return out;
}

}  // namespace lathectl::sim
