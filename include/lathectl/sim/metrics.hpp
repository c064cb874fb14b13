#pragma once
// Metrics every system's study uses: alarm onsets, moving averages, means over a time span.
// (System-specific metrics live in their folders, src/systems/<x>/metrics.hpp.)

#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "lathectl/sensors/faults.hpp"

namespace lathectl::sim {

struct AlarmEvent {
  double time_s = 0.0;
  int code = 0;
};

// Alarm onsets (0 → 1 on the alarm channel) with their reason codes, and the delay of the first
// onset after the first injected fault (NaN if none). Shared by every system's metrics.
std::vector<AlarmEvent> alarm_onsets(std::span<const double> t, std::span<const double> alarm,
                                     std::span<const double> reason,
                                     const std::vector<sensors::SensorFault>& faults,
                                     double& first_delay_s);
// The same, sample by sample as a run records (a streamed Recorder keeps no columns).
class AlarmOnsets {
 public:
  explicit AlarmOnsets(const std::vector<sensors::SensorFault>& faults);
  void push(double t, double alarm, double reason);
  [[nodiscard]] const std::vector<AlarmEvent>& events() const noexcept { return out_; }
  [[nodiscard]] double first_delay_s() const noexcept { return first_delay_s_; }

 private:
  double first_fault_ = std::numeric_limits<double>::infinity();
  double first_delay_s_ = std::numeric_limits<double>::quiet_NaN();
  bool was_ = false;
  std::vector<AlarmEvent> out_;
};

// Centered-free trailing moving average over `window` samples.
std::vector<double> moving_average(std::span<const double> x, std::size_t window);
// The same sample by sample (bit-identical; keeps the last `window` samples only).
class MovingAverage {
 public:
  explicit MovingAverage(std::size_t window = 1);
  double push(double x) noexcept;

 private:
  std::vector<double> ring_;
  std::size_t n_ = 0;
  double acc_ = 0.0;
};
// Mean of x over samples whose time lies in [t0, t1).
double mean_between(std::span<const double> t, std::span<const double> x, double t0, double t1);
// The same sample by sample (bit-identical).
struct MeanBetween {
  double t0 = 0.0, t1 = 0.0, sum = 0.0;
  std::size_t n = 0;
  void push(double t, double x) noexcept {
    if (t >= t0 && t < t1) {
      sum += x;
      ++n;
    }
  }
  [[nodiscard]] double value() const noexcept {
    return n ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
  }
};

}  // namespace lathectl::sim
