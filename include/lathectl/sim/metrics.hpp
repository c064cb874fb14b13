#pragma once
// Metrics every system's study uses: alarm onsets, moving averages, means over a time span.
// (System-specific metrics live in their folders, src/systems/<x>/metrics.hpp.)

#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "lathectl/sim/faults.hpp"

namespace lathectl::sim {

struct AlarmEvent {
  double time_s = 0.0;
  int code = 0;
};

// Alarm onsets (0 → 1 on the alarm channel) with their reason codes, and the delay of the first
// onset after the first injected fault (NaN if none). Shared by every system's metrics.
std::vector<AlarmEvent> alarm_onsets(std::span<const double> t, std::span<const double> alarm,
                                     std::span<const double> reason,
                                     const std::vector<SensorFault>& faults, double& first_delay_s);

// Centered-free trailing moving average over `window` samples.
std::vector<double> moving_average(std::span<const double> x, std::size_t window);
// Mean of x over samples whose time lies in [t0, t1).
double mean_between(std::span<const double> t, std::span<const double> x, double t0, double t1);

}  // namespace lathectl::sim
