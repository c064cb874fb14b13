#include "lathectl/control/slide_machine.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::control {

namespace {
void check_law(const std::vector<SlideMachine::LawPoint>& law, const char* name) {
  for (std::size_t i = 0; i < law.size(); ++i) {
    if (!std::isfinite(law[i].position_m) || !std::isfinite(law[i].value) || !(law[i].value > 0.0))
      throw core::ParameterError(name, std::string(name) + ": point " + std::to_string(i) +
                                           " needs a finite position and a value > 0");
    if (i > 0 && !(law[i].position_m > law[i - 1].position_m))
      throw core::ParameterError(name, std::string(name) + ": positions must rise");
  }
}
}  // namespace

double SlideMachine::law_at(const std::vector<LawPoint>& law, double x) noexcept {
  if (law.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (!(x > law.front().position_m)) return law.front().value;
  if (!(x < law.back().position_m)) return law.back().value;
  const auto hi = std::upper_bound(law.begin(), law.end(), x, [](double v, const LawPoint& p) {
    return v < p.position_m;
  });
  const auto lo = hi - 1;
  const double w = (x - lo->position_m) / (hi->position_m - lo->position_m);
  return lo->value + w * (hi->value - lo->value);
}

void SlideMachine::configure(const Params& p) {
  if (!(p.overload_factor > 1.0))
    throw core::ParameterError("overload_factor", "overload factor must be > 1 (∞: off)");
  if (!(p.overload_time_s >= 0.0) || !std::isfinite(p.overload_time_s))
    throw core::ParameterError("overload_time_s", "overload time must be finite and ≥ 0");
  if (!(p.breakage_drop > 0.0))
    throw core::ParameterError("breakage_drop", "breakage drop must be > 0 (∞: off)");
  const double period = p.controller.period_s;
  if (!(p.breakage_window_s >= period) ||
      !(p.breakage_window_s <= period * static_cast<double>(kBreakageSamples - 1)))
    throw core::ParameterError(
        "breakage_window_s", "breakage window must span 1 … " +
                                 std::to_string(kBreakageSamples - 1) + " control periods");
  check_law(p.feed_law, "feed_law");
  check_law(p.force_law, "force_law");
  ctl_.configure(p.controller);  // its own ParameterError, naming its parameter
  p_ = p;
  // The window in samples (one push per control period), the samples before the present one.
  hist_n_ = static_cast<std::size_t>(std::llround(p.breakage_window_s / period));
  collapse_.configure(static_cast<double>(hist_n_));
  over_limit_n_ = std::llround(p.overload_time_s / period);
  configured_ = true;
  start(0.0);
}

void SlideMachine::start(double force_N) noexcept {
  if (!configured_) return;
  ctl_.program(p_.controller.mode, p_.controller.feed_m_per_s, p_.controller.force_set_N);
  ctl_.start(force_N);
  enabled_ = true;
  alarm_ = false;
  alarm_reason_ = Reason::None;
  over_n_ = 0;
  collapse_.reset();
  co_ = {};
  out_ = {};
  out_.enabled = true;
  out_.mode = p_.controller.mode;
  out_.force_estimate_N = force_N;
  out_.feed_set_m_per_s = p_.controller.feed_m_per_s;
  out_.force_set_N = p_.controller.force_set_N;
}

void SlideMachine::latch(Reason r) noexcept {
  if (alarm_) return;
  alarm_ = true;
  alarm_reason_ = r;
}

// update()'s phases, in the order they run.

// Slide off: valve shut, the controller not run.
void SlideMachine::switch_off() noexcept {
  enabled_ = false;
  out_.slot_m = ctl_.params().modulation == Modulation::Amplitude ? 0.0 : ctl_.params().slot_m;
  out_.frequency_Hz = 0.0;
  out_.pulses = false;
  out_.feed_cmd_m_per_s = 0.0;
  out_.enabled = false;
  out_.alarm = alarm_ || co_.alarm;
  out_.alarm_reason = alarm_ ? alarm_reason_ : co_.alarm_reason;
  out_.reason = out_.alarm ? out_.alarm_reason : Reason::SlideOff;
}

// The program: mode and setpoints, the laws along the travel over the programmed values; on
// switching on, the controller starts bumpless from the force the sensor reads now.
void SlideMachine::program(const Input& in) noexcept {
  double feed = in.feed_m_per_s;
  double force = in.force_set_N;
  if (!p_.feed_law.empty()) feed = law_at(p_.feed_law, in.position_m);
  if (!p_.force_law.empty()) force = law_at(p_.force_law, in.position_m);
  ctl_.program(in.mode, feed, force);
  if (!enabled_) {  // switched on: bumpless from the force the sensor reads now
    enabled_ = true;
    const auto& cp = ctl_.params();
    const double f0 = (in.sensor_V - cp.sensor_offset_V) / cp.sensor_V_per_N;
    const bool held = co_.alarm;  // a sensor alarm stays latched through off/on
    if (!held) ctl_.start(std::isfinite(f0) ? std::max(f0, 0.0) : 0.0);
    over_n_ = 0;
    collapse_.reset();
  }
}

// The outputs: the controller's, unless the machine's own alarm stops the feed.
void SlideMachine::write_outputs(double est) noexcept {
  const auto& cp = ctl_.params();
  out_.slot_m = co_.slot_m;
  out_.frequency_Hz = co_.frequency_Hz;
  out_.feed_cmd_m_per_s = co_.feed_cmd_m_per_s;
  out_.reason = co_.reason;
  out_.alarm = co_.alarm;
  out_.alarm_reason = co_.alarm_reason;
  if (alarm_ && !co_.alarm) {  // the machine's own alarm: stop the feed, valve shut
    if (cp.modulation == Modulation::Amplitude) out_.slot_m = 0.0;
    out_.frequency_Hz = 0.0;
    out_.feed_cmd_m_per_s = 0.0;
    out_.reason = alarm_reason_;
    out_.alarm = true;
    out_.alarm_reason = alarm_reason_;
  }
  // The valve pulses unless the feed is stopped (roughing's alarm stop: slot or frequency 0).
  out_.pulses =
      out_.frequency_Hz > 0.0 && out_.slot_m > 0.0 && !(out_.alarm && out_.feed_cmd_m_per_s <= 0.0);
  out_.force_estimate_N = est;
  out_.feed_set_m_per_s = cp.feed_m_per_s;
  out_.force_set_N = cp.force_set_N;
  out_.mode = cp.mode;
  out_.enabled = true;
}

void SlideMachine::update(const Input& in) noexcept {
  if (!configured_) {
    out_ = {};
    return;
  }
  if (in.reset_alarm && !last_reset_) {
    alarm_ = false;
    alarm_reason_ = Reason::None;
    over_n_ = 0;
    collapse_.reset();
    ctl_.reset_alarm();
  }
  last_reset_ = in.reset_alarm;

  if (!in.enable) {  // slide off: valve shut, the controller not run
    switch_off();
    return;
  }

  program(in);
  ctl_.update({in.sensor_V}, co_);
  const auto& cp = ctl_.params();
  const bool roughing = cp.mode == Mode::Roughing;
  const double est = co_.force_estimate_N;
  collapse_.push(est, 1.0);  // one sample per control period

  // Roughing's tool alarms (only when the sensor itself is trusted).
  if (roughing && !co_.alarm && !alarm_) {
    const double set = cp.force_set_N;
    over_n_ = est > p_.overload_factor * set ? over_n_ + 1 : 0;
    if (over_n_ > over_limit_n_) latch(Reason::Overload);
    // (a whole window of samples before this one since the last restart)
    if (collapse_.pushed() > hist_n_ && collapse_.fell_by(est, p_.breakage_drop * set) &&
        co_.feed_cmd_m_per_s > 0.0)
      latch(Reason::ToolBreakage);
  } else if (!roughing) {
    over_n_ = 0;
  }

  write_outputs(est);
}

}  // namespace lathectl::control
