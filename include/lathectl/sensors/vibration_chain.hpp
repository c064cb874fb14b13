#pragma once
// Measurement chain of seed 001 (system B), as a real one behaves.
//
// Vibration: sensor 16 → amplifier 17 with the dead zone of setter 18 → ADC 19 (amplitude a0) and
// frequency detector 20 (ω_d).
//   sensor: displacement of the part at the tool [m] + white noise (σ per sample), then a
//           second-order Butterworth high-pass at highpass_Hz (the sensor and its coupling pass no
//           static deflection: slow feed-induced bending is not vibration)
//   amplifier: gate dead zone: |x| < dead_zone → 0, else x (so a0 is unbiased above it)
//   amplitude: peak of |x| over each gate of amplitude_gate_s, quantised to adc_lsb_m, published
//           at the gate's end (a delay of one gate); 0 when the amplifier output stayed zero
//   frequency: crossings of ±dead_zone/2 (hysteresis) counted over frequency_gate_s:
//           f = crossings/(2·gate), resolution 1/(2·gate) Hz, published at the gate's end;
//           0 when fewer than 2 crossings
// A real sensor (update_acceleration): an accelerometer's acceleration [m/s²], no simulated noise.
//   It passes a second high-pass at the same highpass_Hz (the same HighPass2), then two
//   trapezoidal integrations (velocity, displacement), then the chain's own high-pass above:
//   a → HP → ∫ → ∫ → HP → dead zone → detectors. The first high-pass's double zero at 0 Hz
//   cancels the integrators' double pole, so HP·∫∫ is a stable low-pass (its DC gain
//   1/(2π·highpass_Hz)², prewarped): an offset of the signal (the interface's DC, the sensor's
//   bias, gravity on a DC-coupled sensor) becomes a constant displacement, which the chain's
//   high-pass removes; no state grows. The cost is the second high-pass's gain at the chatter
//   frequency f: displacement amplitude = A/(2πf)² · G(f)², G(f) = 1/√(1 + (f_c/f)⁴) (each
//   high-pass; prewarped bilinear: tan(π·f_c·T)/tan(π·f·T) for f_c/f, and the trapezoid's gain
//   T/(2·tan(π·f·T)) for 1/(2πf)), against G(f) for a displacement. At f_c = 40 Hz:
//   G² = 0.975 at 100 Hz, 0.9984 at 200 Hz, 0.9990 at 226 Hz; 0.71 at 50 Hz.
// Power: sensor 11 (active power of the main motor, first-order lag, noise, ADC) → idle
// compensation: switch 12 + compensator 13 store N_idle while the NC block flagged "idle" runs
// (averaged over its last idle_average_s, at that block's speed) and adder 14 gives
// N_c = N_m − N_idle. Beyond the seed: a speed-dependent idle table (rpm → W, linear
// interpolation) replaces the stored value, so a speed change in cut does not read as cutting
// power.
// All update() calls are noexcept and allocation-free (the idle table is sized in configure()).

#include <random>
#include <vector>

#include "lathectl/sensors/force_sensor.hpp"

namespace lathectl::sensors {

// Second-order Butterworth high-pass, bilinear transform prewarped at the cut-off.
class HighPass2 {
 public:
  void configure(double cutoff_Hz, double sample_period_s) noexcept;
  double step(double x) noexcept {  // in the header: a rig steps it every step
    const double y = b0_ * x + b1_ * x1_ + b2_ * x2_ - a1_ * y1_ - a2_ * y2_;
    x2_ = x1_;
    x1_ = x;
    y2_ = y1_;
    y1_ = y;
    return y;
  }

 private:
  double b0_ = 1, b1_ = 0, b2_ = 0, a1_ = 0, a2_ = 0;
  double x1_ = 0, x2_ = 0, y1_ = 0, y2_ = 0;
};

class VibrationChain {
 public:
  struct Params {
    double sample_period_s = 1e-4;
    double highpass_Hz = 40.0;
    double noise_m = 0.2e-6;    // σ per sample
    double dead_zone_m = 5e-6;  // setter 18
    double amplitude_gate_s = 0.05;
    double frequency_gate_s = 0.1;
    double adc_lsb_m = 1e-6;
    unsigned seed = 1;
    bool operator==(const Params&) const = default;
  };
  void configure(const Params& p);  // throws std::invalid_argument
  void update(double displacement_m) noexcept;
  // A real accelerometer's sample [m/s²] at sample_period_s: integrated to displacement behind
  // its own high-pass (above); noise_m is not added. Use one of update() and this per chain.
  void update_acceleration(double acceleration_m_s2) noexcept;
  // The displacement the acceleration's integrations give, before the chain's high-pass [m].
  [[nodiscard]] double integrated_m() const noexcept { return displacement_; }
  // The high-passed displacement, before the dead zone [m].
  [[nodiscard]] double sensor_m() const noexcept { return sensor_; }
  [[nodiscard]] double amplifier_m() const noexcept { return amp_; }  // after the dead zone
  [[nodiscard]] double a0_m() const noexcept { return a0_; }          // ADC 19
  [[nodiscard]] double omega_d() const noexcept { return omega_d_; }  // detector 20 [rad/s]
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  Params p_{};
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> noise_{0.0, 1.0};
  void detect(double highpassed_m) noexcept;  // dead zone, ADC 19, detector 20
  HighPass2 highpass_;
  HighPass2 accel_highpass_;  // update_acceleration's, before the integrations
  double accel_ = 0.0, velocity_ = 0.0, displacement_ = 0.0;
  double sensor_ = 0.0;
  double amp_ = 0.0;
  double peak_ = 0.0, a_timer_ = 0.0, a0_ = 0.0;
  int crossings_ = 0, sign_ = 0;
  double f_timer_ = 0.0, omega_d_ = 0.0;
};

class PowerSensor {
 public:
  struct Params {
    LaggedNoisySensor::Params meter{0.05, 5.0, 1e6, 2};  // lag, noise σ [W], range, seed
    double adc_lsb_W = 1.0;
    double idle_average_s = 0.2;
    // Beyond the seed: rpm → idle W; empty = the seed's stored value.
    std::vector<double> idle_table_rpm;
    std::vector<double> idle_table_W;
    bool operator==(const Params&) const = default;
  };
  void configure(const Params& p, double dt);  // throws std::invalid_argument
  // motor_power_W: the drive's true electrical power; idle_block: the NC block is flagged idle.
  void update(double motor_power_W, double rpm, bool idle_block) noexcept;
  [[nodiscard]] double idle_W() const noexcept { return idle_; }
  [[nodiscard]] double cutting_W() const noexcept { return cutting_; }  // N_c
  [[nodiscard]] double idle_stored_rpm() const noexcept { return idle_rpm_; }

 private:
  [[nodiscard]] double table(double rpm) const noexcept;
  Params p_{};
  double dt_ = 1e-3;
  LaggedNoisySensor meter_;
  double measured_ = 0.0, idle_ = 0.0, cutting_ = 0.0, idle_rpm_ = 0.0;
  double avg_ = 0.0;  // running average over the idle block
  bool was_idle_ = false;
  bool started_ = false;
};

}  // namespace lathectl::sensors
