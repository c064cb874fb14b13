#include "lathectl/sensors/force_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::sensors {

void LaggedNoisySensor::configure(const Params& p) {
  if (!(p.time_constant_s >= 0.0) || !std::isfinite(p.time_constant_s))
    throw std::invalid_argument("lagged sensor: time_constant_s must be >= 0");
  if (!(p.noise_sigma >= 0.0) || !std::isfinite(p.noise_sigma))
    throw std::invalid_argument("lagged sensor: noise_sigma must be >= 0");
  if (!(p.range > 0.0)) throw std::invalid_argument("lagged sensor: range must be > 0");
  p_ = p;
  rng_.seed(p.seed);
  normal_.reset();
  y_ = 0.0;
  last_dt_ = -1.0;
}

void LaggedNoisySensor::reset(double value) noexcept {
  y_ = value;
}

void LaggedNoisySensor::step(double dt, double true_value) noexcept {
  if (dt != last_dt_) {  // the step is fixed in a run: one exp per run, not per step
    last_dt_ = dt;
    lag_ = core::FirstOrderLag(dt, p_.time_constant_s);
  }
  y_ = lag_.step(y_, true_value);
}

double LaggedNoisySensor::sample() noexcept {
  const double noise = p_.noise_sigma > 0.0 ? p_.noise_sigma * normal_(rng_) : 0.0;
  return std::clamp(y_ + noise, -p_.range, p_.range);
}

}  // namespace lathectl::sensors
