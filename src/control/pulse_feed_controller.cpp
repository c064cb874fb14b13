#include "lathectl/control/pulse_feed_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::control {

void PulseFeedController::configure(const Params& p) {
  auto need = [](bool ok, const char* what, const char* parameter) {
    if (!ok)
      throw core::ParameterError(parameter, std::string("pulse feed controller: ") + what);
  };
  need(p.period_s > 0.0, "period must be > 0", "period_s");
  need(p.regulator_gain_per_m > 0.0, "regulator gain must be > 0", "regulator_gain_per_m");
  need(p.pulse_width_s > 0.0, "pulse width must be > 0", "pulse_width_s");
  need(p.piston_area_m2 > 0.0, "piston area must be > 0", "piston_area_m2");
  need(p.leak_m3_per_s_Pa >= 0.0 && p.friction_N >= 0.0, "leakage and friction must be ≥ 0", "leak_m3_per_s_Pa");
  need(p.feed_m_per_s > 0.0, "programmed feed must be > 0", "feed_m_per_s");
  need(p.sensor_V_per_N > 0.0, "sensor gain must be > 0", "sensor_V_per_N");
  need(p.force_filter_s >= 0.0, "force filter time must be ≥ 0", "force_filter_s");
  need(p.compliance_m3_per_Pa >= 0.0 && p.rate_filter_s >= 0.0, "compliance and rate filter ≥ 0", "compliance_m3_per_Pa");
  need(p.duty_max > 0.0 && p.duty_max <= 1.0, "duty_max must be in (0, 1]", "duty_max");
  need(p.feed_min_fraction >= 0.0 && p.feed_min_fraction < 1.0, "feed_min_fraction in [0, 1)", "feed_min_fraction");
  if (p.mode == Mode::Roughing) need(p.force_set_N > 0.0, "force setpoint must be > 0", "force_set_N");
  if (p.modulation == Modulation::Amplitude) {
    need(p.frequency_Hz > 0.0 && p.frequency_Hz * p.pulse_width_s <= 1.0, "AIM needs 0 < f·Δt ≤ 1", "frequency_Hz");
    need(p.slot_min_m >= 0.0 && p.slot_max_m > p.slot_min_m, "slot limits: 0 ≤ min < max", "slot_max_m");
  } else {
    need(p.slot_m > 0.0, "FIM slot must be > 0", "slot_m");
    need(p.frequency_min_Hz >= 0.0 && p.frequency_max_Hz > p.frequency_min_Hz,
         "frequency limits: 0 ≤ min < max", "frequency_max_Hz");
    need(p.frequency_ramp_Hz_per_s > 0.0, "converter ramp must be > 0", "frequency_ramp_Hz_per_s");
  }
  p_ = p;
  configured_ = true;
  ka_ = p.regulator_gain_per_m * p.pulse_width_s * p.frequency_Hz;  // (2)
  kf_ = p.regulator_gain_per_m * p.slot_m * p.pulse_width_s;        // (6)
  force_lag_ = core::FirstOrderLag(p.period_s, p.force_filter_s);
  rate_lag_ = core::FirstOrderLag(p.period_s, p.rate_filter_s);
  {
    auto mp = p.sensor_monitor;  // the monitor samples once per control period
    if (mp.period_s == 0.0) mp.period_s = p.period_s;
    monitor_.configure(mp);
  }
  pi_.configure({p.kp, p.ti_s, p.feed_min_fraction, 1.0});
  if (p.modulation == Modulation::Frequency) ramp_.configure(p.frequency_ramp_Hz_per_s);
  start(0.0);
}

double PulseFeedController::actuator_for(double feed, double load_N,
                                         double load_rate) const noexcept {
  const double q = feed * p_.piston_area_m2 +
                   p_.leak_m3_per_s_Pa * (load_N + p_.friction_N) / p_.piston_area_m2 +  // (3)
                   p_.compliance_m3_per_Pa * load_rate / p_.piston_area_m2;
  return p_.modulation == Modulation::Amplitude ? q / ka_ : q / kf_;
}

void PulseFeedController::start(double force_N) noexcept {
  force_ = force_N;
  force_rate_ = 0.0;
  pi_.preset(1.0);
  monitor_.reset();
  alarm_ = false;
  alarm_reason_ = Reason::None;
  const double a = actuator_for(p_.feed_m_per_s, force_N);
  last_ = {};
  last_.force_estimate_N = force_N;
  last_.feed_cmd_m_per_s = p_.feed_m_per_s;
  if (p_.modulation == Modulation::Amplitude) {
    last_.slot_m = std::clamp(a, p_.slot_min_m, p_.slot_max_m);
    last_.frequency_Hz = p_.frequency_Hz;
  } else {
    const double f_hi = std::min(p_.frequency_max_Hz, p_.duty_max / p_.pulse_width_s);
    last_.frequency_Hz = std::clamp(a, p_.frequency_min_Hz, f_hi);
    last_.slot_m = p_.slot_m;
    ramp_.reset(last_.frequency_Hz);
  }
}

void PulseFeedController::program(Mode mode, double feed_m_per_s, double force_set_N) noexcept {
  if (!configured_) return;
  if (std::isfinite(feed_m_per_s) && feed_m_per_s > 0.0 && feed_m_per_s != p_.feed_m_per_s) {
    // The regulator's output is a fraction of the programmed feed: rescale it so that the feed
    // it commands does not jump with the new program (bumpless), within its limits.
    const double u = pi_.output() * p_.feed_m_per_s / feed_m_per_s;
    pi_.preset(std::clamp(u, p_.feed_min_fraction, 1.0));
    p_.feed_m_per_s = feed_m_per_s;
  }
  if (std::isfinite(force_set_N) && force_set_N > 0.0) p_.force_set_N = force_set_N;
  if (mode != p_.mode) {
    // Into roughing the regulator starts at the programmed feed (u = 1), as at a start.
    if (mode == Mode::Roughing) pi_.preset(1.0);
    p_.mode = mode;
  }
}

void PulseFeedController::reset_alarm() noexcept {
  alarm_ = false;
  alarm_reason_ = Reason::None;
  monitor_.reset();
}

// An alarm holds the last output; roughing stops the feed (no flow into the cylinder).
void PulseFeedController::hold_on_alarm(Output& out) noexcept {
  out = last_;
  if (p_.mode == Mode::Roughing) {  // stop the feed: no flow into the cylinder
    out.feed_cmd_m_per_s = 0.0;
    if (p_.modulation == Modulation::Amplitude)
      out.slot_m = 0.0;
    else
      out.frequency_Hz = 0.0;
    if (p_.modulation == Modulation::Frequency) ramp_.reset(0.0);
  }
  out.reason = alarm_reason_;
  out.alarm = true;
  out.alarm_reason = alarm_reason_;
  last_ = out;
}

// The actuator's command for `a`, in its range (AIM: the slot; FIM: the frequency, ramped), never
// up on a suspect reading.
void PulseFeedController::command_actuator(double a, bool suspect, Reason& reason,
                                           Output& out) noexcept {
  if (p_.modulation == Modulation::Amplitude) {
    out.slot_m = std::clamp(a, p_.slot_min_m, p_.slot_max_m);
    out.frequency_Hz = p_.frequency_Hz;
    if (suspect && out.slot_m > last_.slot_m) {
      out.slot_m = last_.slot_m;
      reason = Reason::SensorSuspect;
    }
    if (a > p_.slot_max_m && reason == Reason::None) reason = Reason::OutputHigh;
    if (a < p_.slot_min_m && reason == Reason::None) reason = Reason::OutputLow;
  } else {
    const double f_hi = std::min(p_.frequency_max_Hz, p_.duty_max / p_.pulse_width_s);
    double f = std::clamp(a, p_.frequency_min_Hz, f_hi);
    if (suspect && f > last_.frequency_Hz) {
      f = last_.frequency_Hz;
      reason = Reason::SensorSuspect;
    }
    if (a > f_hi && reason == Reason::None) reason = Reason::OutputHigh;
    if (a < p_.frequency_min_Hz && reason == Reason::None) reason = Reason::OutputLow;
    bool ramped = false;
    out.frequency_Hz = ramp_.update(f, p_.period_s, ramped);
    if (ramped && reason == Reason::None) reason = Reason::RateLimited;
    out.slot_m = p_.slot_m;
  }
}

void PulseFeedController::update(const Input& in, Output& out) noexcept {
  if (!configured_) {
    out = {};
    return;
  }
  const Reason fault = monitor_.check(in.sensor_V, p_.period_s);
  if (fault != Reason::None && !alarm_) {
    alarm_ = true;
    alarm_reason_ = fault;
  }
  if (alarm_) {
    hold_on_alarm(out);
    return;
  }

  const double measured = (in.sensor_V - p_.sensor_offset_V) / p_.sensor_V_per_N;
  const double previous = force_;
  force_ = force_lag_.step_increment(force_, measured);
  force_rate_ = rate_lag_.step_increment(force_rate_, (force_ - previous) / p_.period_s);

  Reason reason = Reason::None;
  // A frozen reading (suspect, see SignalMonitor) never drives the feed up: the regulator and
  // the actuator may hold or fall, not rise, until the reading moves again.
  const bool suspect = monitor_.suspect();
  double u = 1.0;
  if (p_.mode == Mode::Roughing) {
    const PiRegulator before = pi_;
    const double u_prev = pi_.output();
    u = pi_.update((p_.force_set_N - force_) / p_.force_set_N, p_.period_s, reason);
    if (suspect && u > u_prev) {  // freeze the regulator: no rise, and no windup meanwhile
      pi_ = before;
      u = u_prev;
      reason = Reason::SensorSuspect;
    }
  }
  const double feed = u * p_.feed_m_per_s;
  const double rate = p_.mode == Mode::Finishing ? force_rate_ : 0.0;
  const double a = actuator_for(feed, std::max(force_, 0.0), rate);

  out.force_estimate_N = force_;
  out.feed_cmd_m_per_s = feed;
  out.alarm = false;
  out.alarm_reason = Reason::None;
  command_actuator(a, suspect, reason, out);
  out.reason = reason;
  last_ = out;
}

}  // namespace lathectl::control
