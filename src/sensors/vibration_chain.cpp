#include "lathectl/sensors/vibration_chain.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::sensors {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}
}  // namespace

void HighPass2::configure(double cutoff_Hz, double dt) noexcept {
  const double k = std::tan(std::numbers::pi * cutoff_Hz * dt);
  const double q = std::numbers::sqrt2;
  const double norm = 1.0 / (1.0 + q * k + k * k);
  b0_ = norm;
  b1_ = -2.0 * norm;
  b2_ = norm;
  a1_ = 2.0 * (k * k - 1.0) * norm;
  a2_ = (1.0 - q * k + k * k) * norm;
  x1_ = x2_ = y1_ = y2_ = 0.0;
}

void VibrationChain::configure(const Params& p) {
  require(p.sample_period_s > 0.0, "vibration chain: sample_period_s must be positive");
  require(p.highpass_Hz > 0.0 && p.highpass_Hz < 0.25 / p.sample_period_s,
          "vibration chain: highpass_Hz must be in (0, sampling rate / 4)");
  require(p.noise_m >= 0.0 && p.dead_zone_m >= 0.0 && p.adc_lsb_m > 0.0,
          "vibration chain: noise and dead zone must be non-negative, adc_lsb positive");
  require(p.amplitude_gate_s >= p.sample_period_s && p.frequency_gate_s >= p.sample_period_s,
          "vibration chain: gates must be at least one sample");
  p_ = p;
  rng_.seed(p.seed);
  highpass_.configure(p.highpass_Hz, p.sample_period_s);
  accel_highpass_.configure(p.highpass_Hz, p.sample_period_s);
  accel_ = velocity_ = displacement_ = sensor_ = 0.0;
  amp_ = peak_ = a_timer_ = a0_ = f_timer_ = omega_d_ = 0.0;
  crossings_ = sign_ = 0;
}

void VibrationChain::update(double x) noexcept {
  x += p_.noise_m * noise_(rng_);
  detect(highpass_.step(x));
}

void VibrationChain::update_acceleration(double a) noexcept {
  // Trapezoidal integration of the high-passed acceleration, twice.
  const double h = accel_highpass_.step(a);
  const double half = 0.5 * p_.sample_period_s;
  const double v = velocity_ + half * (h + accel_);
  displacement_ += half * (v + velocity_);
  velocity_ = v;
  accel_ = h;
  detect(highpass_.step(displacement_));
}

void VibrationChain::detect(double y) noexcept {
  sensor_ = y;
  amp_ = std::abs(y) < p_.dead_zone_m ? 0.0 : y;

  peak_ = std::max(peak_, std::abs(amp_));
  a_timer_ += p_.sample_period_s;
  if (a_timer_ >= p_.amplitude_gate_s - 1e-12) {
    a0_ = std::floor(peak_ / p_.adc_lsb_m) * p_.adc_lsb_m;
    peak_ = 0.0;
    a_timer_ = 0.0;
  }
  const double h = 0.5 * p_.dead_zone_m;
  const int s = amp_ > h ? 1 : (amp_ < -h ? -1 : 0);
  if (s != 0 && s != sign_) {
    if (sign_ != 0) ++crossings_;
    sign_ = s;
  }
  f_timer_ += p_.sample_period_s;
  if (f_timer_ >= p_.frequency_gate_s - 1e-12) {
    omega_d_ = crossings_ >= 2 ? 2.0 * std::numbers::pi * crossings_ / (2.0 * f_timer_) : 0.0;
    crossings_ = 0;
    f_timer_ = 0.0;
  }
  if (a0_ == 0.0) omega_d_ = 0.0;  // below the dead zone both outputs are zero
}

void PowerSensor::configure(const Params& p, double dt) {
  require(dt > 0.0, "power sensor: period must be positive");
  require(p.adc_lsb_W > 0.0 && p.idle_average_s > 0.0,
          "power sensor: adc_lsb_W and idle_average_s must be positive");
  meter_.configure(p.meter);
  require(p.idle_table_rpm.size() == p.idle_table_W.size(),
          "power sensor: idle table rpm and W must have the same length");
  for (std::size_t i = 1; i < p.idle_table_rpm.size(); ++i)
    require(p.idle_table_rpm[i] > p.idle_table_rpm[i - 1],
            "power sensor: idle table speeds must ascend");
  p_ = p;
  dt_ = dt;
  meter_.reset(0.0);
  measured_ = idle_ = cutting_ = idle_rpm_ = avg_ = 0.0;
  was_idle_ = false;
  started_ = false;
}

double PowerSensor::table(double rpm) const noexcept {
  const auto& r = p_.idle_table_rpm;
  const auto& w = p_.idle_table_W;
  if (rpm <= r.front()) return w.front();
  if (rpm >= r.back()) return w.back();
  const auto it = std::upper_bound(r.begin(), r.end(), rpm);
  const std::size_t i = static_cast<std::size_t>(it - r.begin());
  const double f = (rpm - r[i - 1]) / (r[i] - r[i - 1]);
  return w[i - 1] + f * (w[i] - w[i - 1]);
}

void PowerSensor::update(double motor_power_W, double rpm, bool idle_block) noexcept {
  if (!started_) meter_.reset(motor_power_W);  // the meter was on before the program started
  started_ = true;
  meter_.step(dt_, motor_power_W);
  measured_ = std::round(meter_.sample() / p_.adc_lsb_W) * p_.adc_lsb_W;
  if (idle_block) {
    // Exponential average with the window idle_average_s, restarted at the block's start.
    // (at the start the average is the sample: no lag)
    const core::FirstOrderLag lag =
        was_idle_ ? core::FirstOrderLag(dt_, p_.idle_average_s) : core::FirstOrderLag();
    avg_ = lag.step_increment(avg_, measured_);
    idle_ = avg_;
    idle_rpm_ = rpm;
  }
  was_idle_ = idle_block;
  if (!p_.idle_table_rpm.empty()) idle_ = table(rpm);
  cutting_ = std::max(0.0, measured_ - idle_);
}

}  // namespace lathectl::sensors
