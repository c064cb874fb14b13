#pragma once
// Force-parameter sensors (system E, sensor 4).
//
// Dynamometer: y = F + n, with a first-order lag τ (exact discretisation) and white noise
// n ~ N(0, σ²) drawn per sample (seeded); out-of-range saturates at ±range.
// Power-based: cutting power estimated as P_el − P_idle(n) from the spindle's electrical power
// meter, with the same lag and noise model on the measured power (seed 001's compensator 13 and
// adder 14; here with a speed-dependent idle table rather than one stored value).

#include <cstdint>
#include <random>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::sensors {

class LaggedNoisySensor {
 public:
  struct Params {
    double time_constant_s = 0.002;  // τ
    double noise_sigma = 0.0;        // σ, in the measured unit
    double range = 1e9;              // |output| saturates here
    std::uint64_t seed = 1;
    bool operator==(const Params&) const = default;
  };
  void configure(const Params& p);  // throws std::invalid_argument
  void reset(double value) noexcept;
  void step(double dt, double true_value) noexcept;  // advances the lag
  double sample() noexcept;                          // lagged value + noise, saturated
  [[nodiscard]] double lagged() const noexcept { return y_; }

 private:
  Params p_{};
  double y_ = 0.0;
  double last_dt_ = -1.0;  // the step lag_ is for
  core::FirstOrderLag lag_;
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace lathectl::sensors
