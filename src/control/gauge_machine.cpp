#include "lathectl/control/gauge_machine.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::control {

void GaugeMachine::configure(const Params& p) {
  if (!(p.period_s > 0.0) || !std::isfinite(p.period_s))
    throw core::ParameterError("period_s", "gauge: the sample period must be > 0");
  // The probe oscillates at 2ω: at least 20 samples per period of it for its peak and its
  // rectified mean (the transducer model asks for ω·dt ≤ 0.05, about 60).
  if (p.period_s * 2.0 * p.filter.supply_Hz > 0.05)
    throw core::ParameterError(
        "period_s", "gauge: the sample period must resolve the probe's 2ω (at most " +
                        std::to_string(0.05 / (2.0 * p.filter.supply_Hz)) + " s)");
  if (p.steps.empty() || p.steps.size() > kMaxSteps)
    throw core::ParameterError("steps", "gauge: 1 to " + std::to_string(kMaxSteps) +
                                            " thresholds, each with its command");
  for (std::size_t i = 0; i < p.steps.size(); ++i) {
    const Step& s = p.steps[i];
    if (!std::isfinite(s.threshold_V))
      throw core::ParameterError("steps", "gauge: threshold " + std::to_string(i + 1) +
                                              " must be finite");
    if (i > 0 && !(s.threshold_V > p.steps[i - 1].threshold_V))
      throw core::ParameterError("steps", "gauge: the thresholds must rise step by step (" +
                                              std::to_string(i + 1) + " is not above " +
                                              std::to_string(i) + ")");
    const bool last = i + 1 == p.steps.size();
    if (last != (s.command == Command::Size))
      throw core::ParameterError("steps",
                                 "gauge: the last threshold's command, and only it, is size");
    if (i > 0 && s.command != Command::Size &&
        static_cast<int>(s.command) <= static_cast<int>(p.steps[i - 1].command))
      throw core::ParameterError("steps",
                                 "gauge: the commands must go rough → fine → spark-out → size");
  }
  if (!(p.relay_response_s >= 0.0) || !std::isfinite(p.relay_response_s))
    throw core::ParameterError("relay_response_s", "gauge: the relay's response must be ≥ 0 s");
  if (!(p.arm_after_s >= 0.0) || !std::isfinite(p.arm_after_s))
    throw core::ParameterError("arm_after_s", "gauge: the arming delay must be ≥ 0 s");
  if (std::isnan(p.backstop_m) || p.backstop_m == std::numeric_limits<double>::infinity())
    throw core::ParameterError("backstop_m", "gauge: the backstop must be a position or −∞");
  if (!(p.signal_lost_V >= 0.0) || !std::isfinite(p.signal_lost_V))
    throw core::ParameterError("signal_lost_V", "gauge: the signal-lost level must be ≥ 0 V");
  if (!(p.free_signal_V > 0.0))
    throw core::ParameterError("free_signal_V", "gauge: the free probe's signal must be > 0 V");
  if (!std::isfinite(p.initial_signal_V))
    throw core::ParameterError("initial_signal_V", "gauge: the initial signal must be finite");
  if (!(p.gate_guard_s >= 0.0) || !std::isfinite(p.gate_guard_s))
    throw core::ParameterError("gate_guard_s", "gauge: the guard after an interruption must be "
                                               "≥ 0 s");
  sensors::GaugeFilter f;
  f.configure(p.filter, p.period_s);
  p_ = p;
  filter_ = std::move(f);
  // One supply period: two periods of the probe's 2ω, the rectified signal's peak twice.
  window_n_ = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(1.0 / (p.filter.supply_Hz * p.period_s))));
  // Two supply periods: the period of ω/2, whose harmonics are all the signal carries (the
  // probe's 2ω, and ω and ω/2 when it period-doubles) and all the synchronous filter nulls.
  cycle_.assign(std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(
                                             2.0 / (p.filter.supply_Hz * p.period_s)))),
                0.0);
  reset();
}

void GaugeMachine::reset() noexcept {
  filter_.reset(p_.initial_signal_V);
  prev_ = p_.initial_signal_V;
  rearm();
  out_.signal_V = p_.initial_signal_V;
}

double GaugeMachine::bridge_lag_s(double bridge_s, double count, double period_rev_s,
                                  double supply_Hz) noexcept {
  if (!(bridge_s > 0.0) || !(count > 0.0) || !(period_rev_s > 0.0)) return 0.0;
  // s into a bridge the sample fed is P·(1 + floor(s/P)) old; its mean over the bridge, with
  // n = floor(g/P) whole replays and r = g − n·P left: P·(P·n(n + 1)/2 + (n + 1)·r)/g.
  const double P = 2.0 / supply_Hz, g = bridge_s;
  const double n = std::floor(g / P), r = g - n * P;
  const double mean_delay = P * (P * n * (n + 1.0) / 2.0 + (n + 1.0) * r) / g;
  return count * g / period_rev_s * mean_delay;
}

void GaugeMachine::rearm() noexcept {
  t_ = 0.0;
  quiet_n_ = 0;
  cycle_pos_ = cycle_n_ = 0;
  guard_left_s_ = 0.0;
  round_n_ = 0;
  bridging_ = false;
  const double s = out_.signal_V;
  out_ = Output{};
  out_.signal_V = s;
  out_.next_threshold_V = p_.steps.empty() ? 0.0 : p_.steps.front().threshold_V;
  out_.unreachable = !p_.steps.empty() && p_.steps.front().threshold_V >= p_.free_signal_V;
  out_.reason = out_.unreachable ? Reason::GaugeUnreachable : Reason::None;
}

void GaugeMachine::latch(Reason r) noexcept {
  if (out_.alarm) return;  // the first alarm stays the reason
  out_.alarm = true;
  out_.stop = true;
  out_.reason = r;
}

// update()'s phases, in the order they run.

// An interruption under the probe, or its guard: the last probe period on the round surface
// replayed (once one was read whole; before, nothing to bridge with). Returns what the filter is
// fed: the rectified sample g, or the one replayed.
double GaugeMachine::bridge_interruption(const Input& in, double g) noexcept {
  const double dt = p_.period_s;
  if (in.gate) guard_left_s_ = p_.gate_guard_s;
  const bool bridge = (in.gate || guard_left_s_ > 0.0) && cycle_n_ == cycle_.size();
  if (!in.gate && guard_left_s_ > 0.0) guard_left_s_ -= dt;
  double fed = g;
  if (bridge) {
    // A bridge begins: the ring must hold two supply periods read since the last one, or it
    // would replay older laps' samples and the disturbed probe's (the interruptions too close).
    if (!bridging_ && round_n_ < cycle_.size() && t_ > p_.arm_after_s)
      latch(Reason::GaugeNoRoundSurface);
    fed = cycle_[cycle_pos_];
    round_n_ = 0;
  } else {
    cycle_[cycle_pos_] = g;
    cycle_n_ = std::min(cycle_n_ + 1, cycle_.size());
    ++round_n_;
  }
  bridging_ = bridge;
  cycle_pos_ = (cycle_pos_ + 1) % cycle_.size();
  out_.bridged = bridge;
  return fed;
}

// Thresholds: an upward crossing, interpolated between the two samples, of the next one or of
// a later one — then every one before it trips with it (the signal was already above them when
// the relay armed: their commands are superseded at once).
void GaugeMachine::cross_thresholds(double s) noexcept {
  const double dt = p_.period_s;
  const auto n_steps = static_cast<std::int32_t>(p_.steps.size());
  if (out_.armed && out_.tripped_steps < n_steps) {
    std::int32_t crossed = -1;
    double at = 0.0;
    for (auto j = out_.tripped_steps; j < n_steps; ++j) {
      const double th = p_.steps[static_cast<std::size_t>(j)].threshold_V;
      const double now = s - th, before = prev_ - th;
      if (before < 0.0 && now >= 0.0) {
        crossed = j;
        at = t_ + dt * (1.0 - now / (now - before));
      }
    }
    for (auto j = out_.tripped_steps; j <= crossed; ++j) {
      const double th = p_.steps[static_cast<std::size_t>(j)].threshold_V;
      const double now = s - th, before = prev_ - th;
      out_.trip_time_s = before < 0.0 ? t_ + dt * (1.0 - now / (now - before)) : at;
      trip_at_[static_cast<std::size_t>(j)] = out_.trip_time_s + p_.relay_response_s;
      out_.tripped = true;
      ++out_.tripped_steps;
    }
  }
}

// The relay: each tripped step's command operates t_r after its crossing; the outputs it sets
// and the next threshold.
void GaugeMachine::operate_relay() noexcept {
  const auto n_steps = static_cast<std::int32_t>(p_.steps.size());
  while (out_.step < out_.tripped_steps && t_ >= trip_at_[static_cast<std::size_t>(out_.step)]) {
    out_.command = p_.steps[static_cast<std::size_t>(out_.step)].command;
    ++out_.step;
    if (!out_.alarm)
      out_.reason = out_.command == Command::Size ? Reason::GaugeSize : Reason::GaugeStep;
  }
  out_.size = out_.command == Command::Size;
  out_.stop = out_.size || out_.backstop || out_.alarm;
  if (out_.tripped_steps < n_steps) {
    out_.next_threshold_V = p_.steps[static_cast<std::size_t>(out_.tripped_steps)].threshold_V;
    out_.unreachable = out_.next_threshold_V >= p_.free_signal_V;
    if (out_.unreachable && !out_.alarm && out_.reason == Reason::None)
      out_.reason = Reason::GaugeUnreachable;
  } else {
    out_.next_threshold_V = std::numeric_limits<double>::quiet_NaN();
    out_.unreachable = false;
  }
}

void GaugeMachine::update(const Input& in) noexcept {
  if (in.rearm && !last_rearm_) rearm();
  last_rearm_ = in.rearm;
  const double dt = p_.period_s;
  out_.tripped = false;
  if (!std::isfinite(in.generator_V)) {  // nothing of it reaches the filter
    latch(Reason::SensorNotFinite);
    t_ += dt;
    out_.time_s = t_;
    return;
  }
  const double g = std::abs(in.generator_V);  // rectifier (13)
  const double fed = bridge_interruption(in, g);
  const double s = filter_.step(fed);  // filter (14)
  out_.signal_V = s;
  // Signal lost: no sample of |u| at the level for a whole supply period (a 2ω oscillation
  // reaches its peak four times in one).
  if (g >= p_.signal_lost_V) {
    quiet_n_ = 0;
  } else if (++quiet_n_ >= window_n_ && p_.signal_lost_V > 0.0) {
    latch(Reason::GaugeSignalLost);
  }
  out_.armed = t_ > p_.arm_after_s;
  cross_thresholds(s);
  prev_ = s;
  t_ += dt;
  // The backstop: the limit position reached before the size command operated.
  if (!out_.size && !out_.backstop && in.position_m <= p_.backstop_m) {
    out_.backstop = true;
    latch(Reason::GaugeBackstop);
  }
  operate_relay();
  out_.time_s = t_;
}

}  // namespace lathectl::control
