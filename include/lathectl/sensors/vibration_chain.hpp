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
  double step(double x) noexcept;

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
  [[nodiscard]] double amplifier_m() const noexcept { return amp_; }  // after the dead zone
  [[nodiscard]] double a0_m() const noexcept { return a0_; }          // ADC 19
  [[nodiscard]] double omega_d() const noexcept { return omega_d_; }  // detector 20 [rad/s]
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  Params p_{};
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> noise_{0.0, 1.0};
  HighPass2 highpass_;
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
