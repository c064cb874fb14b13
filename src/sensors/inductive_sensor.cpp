#include "lathectl/sensors/inductive_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::sensors {

void InductiveSensor::configure(const Params& p) {
  if (!(p.holder_stiffness_N_per_m > 0.0) || !(p.gain_V_per_m > 0.0) || !(p.saturation_V > 0.0))
    throw std::invalid_argument("inductive sensor: stiffness, gain and range must be > 0");
  if (p.noise_V < 0.0 || p.time_constant_s < 0.0)
    throw std::invalid_argument("inductive sensor: noise and time constant must be ≥ 0");
  p_ = p;
  rng_.seed(p.seed);
  normal_.reset();
  u_ = p.offset_V;
  last_dt_ = -1.0;
}

void InductiveSensor::set_steady(double force_N) noexcept {
  u_ = p_.offset_V + p_.gain_V_per_m * force_N / p_.holder_stiffness_N_per_m;
}

double InductiveSensor::sample() noexcept {
  const double noise = p_.noise_V > 0.0 ? p_.noise_V * normal_(rng_) : 0.0;
  return std::clamp(u_ + noise, 0.0, p_.saturation_V);
}

}  // namespace lathectl::sensors
