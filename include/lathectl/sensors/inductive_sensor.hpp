#pragma once
// Inductive deflection sensor Д of seed 000: measures the gap δ between tool holder and sensor,
// which shrinks as the radial force Py bends the holder.
//
//   δ = Py / k_holder                       (quasi-static holder deflection) [m]
//   τ_s · dU/dt = U_0 + K_s·δ − U            (sensor and demodulator lag; exact discretisation)
//   U_D = clamp(U + n, 0, U_sat),  n ~ N(0, σ²) white, seeded
// U_D rises with Py, so the adder's ΔU = U0 − U_D falls as the force grows.

#include <algorithm>
#include <cstdint>
#include <random>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::sensors {

class InductiveSensor {
 public:
  struct Params {
    double holder_stiffness_N_per_m = 20e6;  // k_holder
    double gain_V_per_m = 0.1e6;             // K_s (0.1 V/µm)
    double offset_V = 0.0;                   // U_0 at zero force
    double noise_V = 0.0;                    // σ of the additive noise
    double time_constant_s = 0.0;            // τ_s
    double saturation_V = 10.0;              // output range 0..U_sat
    std::uint64_t seed = 1;
  };
  void configure(const Params& p);  // throws std::invalid_argument
  void set_steady(double force_N) noexcept;
  // Advances the lag; returns the noiseless signal clamped to the range [V].
  double step(double dt, double force_N) noexcept;
  // One ADC sample of U_D: the signal plus a fresh noise sample, clamped to the range [V].
  // Noise is drawn per sample (white at the sampling rate), not per simulation step.
  double sample() noexcept;
  [[nodiscard]] double volts_per_newton() const noexcept {
    return p_.gain_V_per_m / p_.holder_stiffness_N_per_m;
  }
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  Params p_{};
  double u_ = 0.0;
  double last_dt_ = -1.0;  // the step lag_ is for
  core::FirstOrderLag lag_;
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// In the header: a rig steps it every step (issue 45 item 6).
inline double InductiveSensor::step(double dt, double force_N) noexcept {
  const double target = p_.offset_V + p_.gain_V_per_m * force_N / p_.holder_stiffness_N_per_m;
  if (dt != last_dt_) {
    last_dt_ = dt;
    lag_ = core::FirstOrderLag(dt, p_.time_constant_s);
  }
  u_ = lag_.step(u_, target);
  return std::clamp(u_, 0.0, p_.saturation_V);
}

}  // namespace lathectl::sensors
