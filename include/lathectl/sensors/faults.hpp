#pragma once
// Sensor faults injected into a rig's measurement: NaN (broken cable), out of range, or stuck at
// the last good sample, each over [at_s, at_s + duration_s). Shared by every rig and by the plant
// (cutting/lathe_plant.hpp).

#include <cmath>
#include <vector>

namespace lathectl::sensors {

struct SensorFault {
  bool operator==(const SensorFault&) const = default;
  enum class Kind { NotFinite, Stuck, OutOfRange } kind = Kind::NotFinite;
  double at_s = 0.0;
  double duration_s = 1e300;
};

class FaultInjector {
 public:
  // The sample the controller sees at time t; `out_of_range` is the value a saturated or
  // shorted sensor reports.
  double apply(const std::vector<SensorFault>& faults, double t, double value,
               double out_of_range) noexcept {
    for (const auto& f : faults) {
      if (t < f.at_s || t >= f.at_s + f.duration_s) continue;
      switch (f.kind) {
        case SensorFault::Kind::NotFinite:
          return std::nan("");
        case SensorFault::Kind::OutOfRange:
          return out_of_range;
        case SensorFault::Kind::Stuck:
          return last_good_;
      }
    }
    last_good_ = value;
    return value;
  }
  void reset(double value) noexcept { last_good_ = value; }

 private:
  double last_good_ = 0.0;
};

}  // namespace lathectl::sensors
