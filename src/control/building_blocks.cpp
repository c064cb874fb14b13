#include "lathectl/control/building_blocks.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::control {

PeriodTime period_time(double measured_s, double nominal_s) noexcept {
  const double m = std::isfinite(measured_s) && measured_s > 0.0 ? measured_s : nominal_s;
  return {std::min(m, PeriodTime::kMaxElapsedS), std::min(m, 2.0 * nominal_s)};
}

void SignalMonitor::configure(const Params& p) {
  if (!(p.min < p.max)) throw std::invalid_argument("signal monitor: min must be below max");
  if (p.stuck_time_s < 0.0 || p.stuck_tolerance < 0.0 || p.noise_sigma < 0.0 || p.period_s < 0.0)
    throw std::invalid_argument(
        "signal monitor: stuck time, tolerance, noise and period must be ≥ 0");
  p_ = p;
  suspect_n_ = suspect_samples_for(p);
  reset();
}

int SignalMonitor::suspect_samples_for(const Params& p) noexcept {
  if (!(p.stuck_time_s > 0.0) || !(p.period_s > 0.0)) return 0;
  const double stuck_n = std::max(1.0, std::floor(p.stuck_time_s / p.period_s));
  double n = 2.0;
  if (p.noise_sigma > 0.0 && p.stuck_tolerance > 0.0) {
    const double prob = std::erf(p.stuck_tolerance / (2.0 * p.noise_sigma));
    n = prob >= 1.0 ? stuck_n : std::max(2.0, std::ceil(std::log(1e-6) / std::log(prob)));
  } else if (!(p.noise_sigma > 0.0) && p.stuck_tolerance > 0.0) {
    n = 2.0;  // noise-free: any repeat within the tolerance is the signal standing still
  }
  return static_cast<int>(std::min(n, stuck_n));
}

void SignalMonitor::reset() noexcept {
  has_last_ = false;
  unchanged_s_ = 0.0;
  repeats_ = 0;
}

Reason SignalMonitor::check(double value, double dt, bool armed) noexcept {
  if (!std::isfinite(value)) return Reason::SensorNotFinite;
  if (value < p_.min || value > p_.max) return Reason::SensorOutOfRange;
  if (p_.stuck_time_s > 0.0) {
    if (has_last_ && std::abs(value - last_) <= p_.stuck_tolerance) {
      unchanged_s_ = armed ? unchanged_s_ + dt : 0.0;
      if (repeats_ < 1000000) ++repeats_;
    } else {
      unchanged_s_ = 0.0;
      repeats_ = 0;
    }
    last_ = value;
    has_last_ = true;
    if (unchanged_s_ >= p_.stuck_time_s) return Reason::SensorStuck;
  }
  return Reason::None;
}

void PiRegulator::configure(const Params& p) {
  if (p.out_min > p.out_max) throw std::invalid_argument("PI regulator: out_min above out_max");
  if (p.kp < 0.0 || p.ti_s < 0.0) throw std::invalid_argument("PI regulator: negative gain");
  p_ = p;
  integral_ = 0.0;
  out_ = std::clamp(0.0, p.out_min, p.out_max);
}

void PiRegulator::set_limits(double out_min, double out_max) noexcept {
  p_.out_min = std::min(out_min, out_max);
  p_.out_max = std::max(out_min, out_max);
}

void PiRegulator::preset(double output) noexcept {
  integral_ = std::clamp(output, p_.out_min, p_.out_max);
  out_ = integral_;
}

void PiRegulator::shift(double delta) noexcept {
  integral_ = std::clamp(integral_ + delta, p_.out_min, p_.out_max);
}

double PiRegulator::update(double error, double dt, Reason& limited) noexcept {
  const double ki = p_.ti_s > 0.0 ? p_.kp / p_.ti_s : 0.0;
  const double raw_before = p_.kp * error + integral_;
  // Conditional integration (clamping): the integrator stops while the output sits on a limit
  // and the error would push it further in, and it never leaves the output range itself. So a
  // regulator parked on its limit leaves it exactly when the error changes sign.
  const bool pushing_out =
      (raw_before >= p_.out_max && error > 0.0) || (raw_before <= p_.out_min && error < 0.0);
  if (!pushing_out) integral_ = std::clamp(integral_ + ki * error * dt, p_.out_min, p_.out_max);
  const double raw = p_.kp * error + integral_;
  limited = Reason::None;
  // On the limit counts as limited, consistently with the integrator's hold above.
  if (raw >= p_.out_max) limited = Reason::OutputHigh;
  if (raw <= p_.out_min) limited = Reason::OutputLow;
  out_ = std::clamp(raw, p_.out_min, p_.out_max);
  return out_;
}

void RateLimiter::configure(double rate_per_s) {
  if (!(rate_per_s > 0.0)) throw std::invalid_argument("rate limiter: rate must be > 0");
  rate_ = rate_per_s;
}

double RateLimiter::update(double target, double dt, bool& limited) noexcept {
  const double step = rate_ * dt;
  const double d = target - y_;
  limited = std::abs(d) > step;
  y_ += std::clamp(d, -step, step);
  return y_;
}

}  // namespace lathectl::control
