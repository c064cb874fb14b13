#include "lathectl/control/adaptive_feed_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "lathectl/cutting/feed_range.hpp"

namespace lathectl::control {

void AdaptiveFeedController::configure(const Params& p) {
  auto need = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("adaptive controller: ") + what);
  };
  need(p.period_s > 0.0, "period must be > 0");
  need(p.load_limit > 0.0, "force limit must be > 0");
  need(p.feed_min_mm_per_rev > 0.0 && p.feed_min_mm_per_rev < p.feed_max_mm_per_rev,
       "feed limits: 0 < s_min < s_max");
  need(p.feed_programmed_mm_per_rev >= p.feed_min_mm_per_rev &&
           p.feed_programmed_mm_per_rev <= p.feed_max_mm_per_rev,
       "programmed feed must lie in [s_min, s_max]");
  need(p.air_feed_mm_per_rev > 0.0, "air feed must be > 0");
  need(p.entry_feed_mm_per_rev >= p.feed_min_mm_per_rev, "entry feed must be ≥ s_min");
  need(p.depth_exponent_xv >= 0.0 && p.depth_planned_mm > 0.0, "x_v ≥ 0 and planned depth > 0");
  need(p.depth_exponent_xv == 0.0 || (p.force_model_C > 0.0 && p.force_model_x > 0.0),
       "the depth-corrected speed law needs the force model (C > 0, x > 0)");
  need(p.speed_programmed_m_per_min > 0.0 && p.feed_planned_mm_per_rev > 0.0,
       "planned speed V_p and feed S_p must be > 0");
  need(p.y_v >= 0.0 && p.y_v < 2.0, "y_v must be in [0, 2)");
  need(p.y_v_ranges >= 0 && p.y_v_ranges <= 3, "y_v table: 0 to 3 feed ranges");
  for (int i = 0; i < p.y_v_ranges; ++i) {
    const auto& r = p.y_v_table[static_cast<std::size_t>(i)];
    need(r.Cv > 0.0 && r.y_v >= 0.0 && r.y_v < 2.0 &&
             (i == 0 || r.feed_max_mm_per_rev >
                            p.y_v_table[static_cast<std::size_t>(i - 1)].feed_max_mm_per_rev),
         "y_v table: Cv > 0, y_v in [0, 2), feed ranges ascending");
  }
  need(p.speed_law_filter_s >= 0.0, "speed-law filter time must be ≥ 0");
  need(p.rpm_min > 0.0 && p.rpm_max > p.rpm_min, "spindle range: 0 < min < max");
  need(60.0 / p.rpm_min / p.period_s < 1e7,
       "one revolution at rpm_min spans more than 1e7 periods");
  need(p.cut_power_max_W > 0.0, "cutting power limit must be > 0");
  need(p.kp >= 0.0 && p.ti_s >= 0.0, "PI gains must be ≥ 0");
  need(p.feed_rate_limit_per_s > 0.0 && p.speed_rate_limit_m_per_min_per_s > 0.0,
       "rate limits must be > 0");
  need(p.air_threshold > 0.0 && p.air_threshold < 0.5, "air threshold in (0, 0.5)");
  need(p.air_time_s >= 0.0 && p.overload_time_s >= 0.0 && p.breakage_drop_window_s >= 0.0,
       "times must be ≥ 0");
  need(p.overload_margin >= 0.0 && p.breakage_spike > 1.0, "overload margin ≥ 0, spike > 1");
  {
    SignalMonitor probe;  // validate before any state changes: a throw leaves the old setup intact
    probe.configure(p.sensor_monitor);
  }
  p_ = p;
  base_ = p;
  {
    auto mp = p.sensor_monitor;  // the monitor samples once per control period
    if (mp.period_s == 0.0) mp.period_s = p.period_s;
    monitor_.configure(mp);
  }
  const double s_prog = p.feed_programmed_mm_per_rev;
  pi_.configure({p.kp * s_prog, p.ti_s, p.feed_min_mm_per_rev, feed_ceiling()});
  feed_ramp_.configure(p.feed_rate_limit_per_s * s_prog);
  speed_ramp_.configure(p.speed_rate_limit_m_per_min_per_s);
  feed_ramp_.reset(s_prog);
  speed_ramp_.reset(p.speed_programmed_m_per_min);
  pi_.preset(s_prog);
  contact_.reset();
  over_s_ = 0.0;
  collapse_.configure(p.breakage_drop_window_s);
  alarm_ = false;
  alarm_reason_ = Reason::None;
  held_rpm_ = 0.0;
  depth_estimate_ = p.depth_planned_mm;
  speed_filter_ = core::FirstOrderLag(p.period_s, p.speed_law_filter_s);
  s_cur_filtered_ = p.feed_planned_mm_per_rev;
  // one revolution at the lowest speed, in control periods (allocated here, never in update())
  rev_mean_ = PerRevolutionMean(p.period_s, p.rpm_min);
  feed_rev_ = PerRevolutionMean(p.period_s, p.rpm_min);
  chip_rev_ = PerRevolutionMean(p.period_s, p.rpm_min);
  trend_ = 0.0;
  trend_lag_rpm_ = -1.0;  // the lag is derived again for this period_s
  configured_ = true;
}

double AdaptiveFeedController::feed_ceiling() const noexcept {
  return p_.allow_above_programmed
             ? p_.feed_max_mm_per_rev
             : std::min(p_.feed_max_mm_per_rev, p_.feed_programmed_mm_per_rev);
}

bool AdaptiveFeedController::set_operation(double load_limit, double feed_min_mm_per_rev,
                                           double feed_max_mm_per_rev, bool adaptive) noexcept {
  if (!configured_ || !std::isfinite(load_limit) || !(load_limit > 0.0) ||
      !std::isfinite(feed_max_mm_per_rev) || !(feed_min_mm_per_rev > 0.0) ||
      !(feed_max_mm_per_rev > feed_min_mm_per_rev))
    return false;
  p_.load_limit = load_limit;
  p_.feed_min_mm_per_rev = feed_min_mm_per_rev;
  p_.feed_max_mm_per_rev = feed_max_mm_per_rev;
  p_.feed_programmed_mm_per_rev =
      std::clamp(base_.feed_programmed_mm_per_rev, feed_min_mm_per_rev, feed_max_mm_per_rev);
  p_.entry_feed_mm_per_rev =
      std::clamp(base_.entry_feed_mm_per_rev, feed_min_mm_per_rev, feed_max_mm_per_rev);
  p_.mode = adaptive ? base_.mode : Mode::Fixed;
  pi_.set_limits(feed_min_mm_per_rev, feed_ceiling());
  return true;
}

void AdaptiveFeedController::reset_alarm() noexcept {
  alarm_ = false;
  rev_mean_.restart();
  feed_rev_.restart();
  chip_rev_.restart();
  alarm_reason_ = Reason::None;
  monitor_.reset();
  over_s_ = 0.0;
  collapse_.reset();
}

// update() in phases, in the order they run; each is the text it was, moved (no formula changed).

inline void AdaptiveFeedController::raise(Reason r) noexcept {
  if (!alarm_) {
    alarm_ = true;
    alarm_reason_ = r;
  }
}

// Monitoring the sensor: validity, stuck, range. The fixed baseline has no sensor. Returns the
// fault found this period (None: none); `suspect` whether the reading is suspect.
inline Reason AdaptiveFeedController::check_sensor(const Input& in, const PeriodTime& measured,
                                            bool& suspect) noexcept {
  suspect = false;
  if (p_.mode == Mode::Fixed) return Reason::None;
  // A constant reading is legitimate with the tool in air (a zero-suppressed dynamometer reads
  // exactly 0 there) and in rapids: the stuck timer runs only while the controller acts on
  // the force in a cut — in cut, or a reading above the air threshold.
  const double limit = p_.load_limit;
  const bool armed = in.feed_block && (contact_.in_cut() || in.force > p_.air_threshold * limit);
  const Reason fault = monitor_.check(in.force, measured.evidence_s, armed);
  if (fault != Reason::None) raise(fault);
  suspect = monitor_.suspect();
  return fault;
}

// Contact, breakage and overload, judged on the raw sample; outside a feed block the controller
// goes inactive. Returns the reason this phase gives (NotInFeedBlock, Engaged or None).
inline Reason AdaptiveFeedController::judge_contact(const Input& in, const PeriodTime& measured,
                                             bool sensor_ok) noexcept {
  const double dt = p_.period_s;
  const double limit = p_.load_limit;
  const double s_prog = p_.feed_programmed_mm_per_rev;
  const bool adaptive = p_.mode != Mode::Fixed;
  Reason reason = Reason::None;
  if (!in.feed_block) {  // rapid: inactive, restart bumpless at the next feed block
    contact_.reset();
    over_s_ = 0.0;
    collapse_.reset();
    pi_.preset(s_prog);
    feed_ramp_.reset(s_prog);
    reason = Reason::NotInFeedBlock;
  } else if (adaptive && sensor_ok && !alarm_ && !(in.reading_unusable && contact_.in_cut())) {
    // (In the cut, a reading that cannot be separated from something else judges no contact,
    // breakage or overload: the contact is kept as it was. Out of the cut it may start one.)
    const double air = p_.air_threshold * limit;
    if (contact_.update(in.force, air, p_.air_time_s, dt, true)) {
      // contact: drop to the entry feed at once, preset the PI there
      const double entry = std::min({feed_ramp_.value(), s_prog, p_.entry_feed_mm_per_rev});
      pi_.preset(entry);
      feed_ramp_.reset(entry);
      reason = Reason::Engaged;
    }
    // Breakage: a spike, or a collapse from a loaded cut to nothing within a few ms.
    if (in.force > p_.breakage_spike * limit) raise(Reason::ToolBreakage);
    collapse_.push(0.5 * limit, measured.elapsed_s, in.force > 0.5 * limit);  // loaded: its level
    // A window of 0 turns the collapse detector off (AdaptiveMachine's path-aware one replaces
    // it): `≤ 0` still fired on a fall from half the limit to air within one control period.
    if (p_.breakage_drop_window_s > 0.0 && collapse_.fell_to(in.force, air))
      raise(Reason::ToolBreakage);
    // Overload: above the limit too long although the feed is already at its minimum.
    const bool at_min = feed_ramp_.value() <= p_.feed_min_mm_per_rev * (1.0 + 1e-9);
    over_s_ = (in.force > (1.0 + p_.overload_margin) * limit && at_min)
                  ? over_s_ + measured.evidence_s
                  : 0.0;
    if (over_s_ >= p_.overload_time_s && p_.overload_time_s > 0.0) raise(Reason::Overload);
  } else if (in.reading_unusable && contact_.in_cut()) {
    collapse_.pass(measured.elapsed_s);  // time passes for the collapse window, unjudged
  }
  return reason;
}

// The regulated force: the mean over the last revolution (or the raw sample).
inline double AdaptiveFeedController::regulated_load(const Input& in, bool sensor_ok) noexcept {
  double regulated = in.force;
  if (sensor_ok) {
    const double mean = rev_mean_.push(in.force, in.rpm);
    // the chip that load was cut at: the feed's mean over the last revolution
    (void)chip_rev_.push(feed_rev_.push(feed_ramp_.value(), in.rpm), in.rpm);
    if (p_.average_per_revolution && in.rpm > 0.0) regulated = mean;
  }
  if (!in.feed_block || !contact_.in_cut()) {  // a new cut, a new average
    rev_mean_.restart();
    feed_rev_.restart();
    chip_rev_.restart();
  }
  return regulated;
}

// What the regulator compares with the limit: the per-revolution mean one revolution ahead
// while it rises,
//   M(t + T) ≈ M(t) + T·dM/dt = M(t) + [L(t) − L(t − T)],
// since the mean over the trailing revolution T has dM/dt = (L(t) − L(t − T))/T exactly. One
// revolution ahead because a feed change reaches that mean only over about one: the chip at an
// angle is the axial advance since the previous revolution (the feed's one-revolution integral,
// half a revolution's lag), and the mean of the load over it is another half. L(t) − L(t − T)
// compares the load at the same angle a revolution apart, so an eccentric blank's
// once-per-revolution swing cancels in it (the sample a revolution back interpolated between
// the two around it), while the trend of a hardness ramp, a deeper allowance or the feed's own
// rise shows at once. It is low-passed over a quarter revolution (the interpolation's residue
// of the swing, the sensor's noise and the random allowance's roughness; a lag of T/4), and
// counted only while it rises: the feed falls at once but rises at its rate limit, so a trend
// of both signs drove it down on every dip of the trend and up only slowly — at 600 rpm on
// e_planned_depth a three-revolution cycle, 62 % of the cut within 5 % where it had been 95 %.
// Without it the mean alone showed a trend a revolution late: on issue 47's forged shafts on
// power (hardness ramps of 2-3 % of load a revolution, random allowances of σ 0.1 mm in a
// 1.5 mm cut) 15 of 40 parts ran 5-6.5 % over the limit; with it 1 of 40, 5.7 %.
inline double AdaptiveFeedController::load_ahead(const Input& in, double regulated,
                                                 bool sensor_ok) noexcept {
  const double ago = sensor_ok && p_.average_per_revolution && in.rpm > 0.0 && rev_mean_.full()
                         ? rev_mean_.revolution_ago(in.rpm)
                         : std::nan("");
  if (!std::isfinite(ago)) {
    trend_ = 0.0;
    return regulated;
  }
  // The change the regulator commanded itself comes out of the trend. The chip at an angle is
  // the axial advance since the previous revolution, h(t) = the commanded feed's mean over the
  // last revolution, and the load L ∝ h^y (y the law's feed exponent, force_model_y; on power
  // P = F·V at the same speed too); so the feed alone makes L(t) = L(t − T)·(h(t)/h(t − T))^y,
  // and only the plant's own change (hardness, depth) is L(t) − L(t − T)·(h(t)/h(t − T))^y.
  // Counted, the feed's own rate-limited rise showed a revolution ahead and the proportional
  // term dropped the feed at once: on e_worn_tool (567 rpm) the prior art cycled every 2.6
  // revolutions, 0.14 ↔ 0.18 mm/rev. (The feed now against a revolution ago, not the chip,
  // reads a drop as the plant's rise for the half revolution the chip lags it: worse.)
  const double s_now = feed_rev_.value(), s_ago = chip_rev_.revolution_ago(in.rpm);
  const double own = s_now > 0.0 && s_ago > 0.0 ? std::pow(s_now / s_ago, p_.force_model_y) : 1.0;
  if (in.rpm != trend_lag_rpm_) {  // its exp() only when the speed changes, not every period
    trend_lag_rpm_ = in.rpm;
    trend_lag_ = core::FirstOrderLag(p_.period_s, 0.25 * 60.0 / in.rpm);
  }
  trend_ = trend_lag_
               .step_increment(trend_, in.force - ago * (std::isfinite(own) ? own : 1.0));
  // What the feed already commanded adds to the mean a revolution ahead, the plant unchanged:
  // held at s(t), the chip goes from h(t) to s(t) over the next revolution, its mean there
  // ≈ (h(t) + s(t))/2, so M(t + T) ≈ M(t)·((h(t) + s(t))/(2·h(t)))^y; counted while it rises,
  // as the trend is (the rise a rate-limited feed has in flight, not its next revolution's).
  const double flight =
      s_now > 0.0 ? std::pow(0.5 * (s_now + feed_ramp_.value()) / s_now, p_.force_model_y) : 1.0;
  return regulated + std::max(trend_, 0.0) +
         std::max(regulated * ((std::isfinite(flight) ? flight : 1.0) - 1.0), 0.0);
}

// The feed the regulator asks for: the PI in a cut, the air feed out of it, under a known rise
// of the depth ahead, and never up on a reading that cannot be trusted.
inline double AdaptiveFeedController::feed_target(const Input& in, double error, bool suspect,
                                           Reason& reason) noexcept {
  double target = p_.feed_programmed_mm_per_rev;
  const PiRegulator pi_before = pi_;
  if (contact_.in_cut()) {
    Reason lim = Reason::None;
    const double drift = in.feed_drift_mm_per_rev_per_s;
    if (std::isfinite(drift) && drift != 0.0) pi_.shift(drift * p_.period_s);
    target = pi_.update(error, regulator_dt(in), lim);
    if (reason == Reason::None) reason = lim;
  } else {
    target = std::min(p_.air_feed_mm_per_rev, p_.feed_max_mm_per_rev);
    if (reason == Reason::None) reason = Reason::AirCut;
  }
  // A known rise of the depth ahead: down to the feed it takes at the limit, before the tool
  // gets there. The PI restarts from the ceiling, so leaving it is bumpless (the ramp limits
  // the rise after it).
  const double ceiling = in.feed_ceiling_mm_per_rev;
  if (std::isfinite(ceiling) && ceiling > 0.0) {
    const double c = std::max(ceiling, p_.feed_min_mm_per_rev);
    if (target > c) {
      target = c;
      if (contact_.in_cut()) pi_.preset(c);
      if (reason == Reason::None || reason == Reason::AirCut || reason == Reason::OutputHigh)
        reason = Reason::StockAhead;
    }
  }
  const bool unusable = in.reading_unusable && contact_.in_cut();
  if ((suspect || unusable) && target > feed_ramp_.value()) {
    // A frozen reading never drives the feed up: hold, with the PI frozen (no windup, and no
    // preset, which would drop the next output by kp·|error| and ratchet the feed down).
    // Nor does a reading that cannot be separated from something else.
    target = feed_ramp_.value();
    pi_ = pi_before;
    reason = suspect ? Reason::SensorSuspect : Reason::PowerAccelerationUnknown;
  }
  return target;
}

// The integral's time step: the control period, counted in revolutions above 600 rpm. The
// regulator acts on the per-revolution mean, and what it meets along the part (a hard spot, a
// collar) passes in revolutions, not seconds: its integral time holds as set up to 600 rpm (a
// revolution of 0.1 s, the default ti_s) and shrinks with the revolution above. At 1300 rpm a
// 5 mm hard spot at 0.4 mm/rev passed in half a second, the integral lagged it and the
// per-revolution power rose 11 % over the limit (issue 47's forged shaft). The feed's ramp
// stays in seconds: counted in revolutions too, entries and corners at 1500-1900 rpm rose
// 5-7 % over on generated parts that held 2.6-3.7 %.
inline double AdaptiveFeedController::regulator_dt(const Input& in) const noexcept {
  constexpr double kReferenceRpm = 600.0;
  return in.rpm > kReferenceRpm ? p_.period_s * (in.rpm / kReferenceRpm) : p_.period_s;
}

// The feed ramp towards the target: down at once, up at its rate limit, with the PI kept from
// storing what the ramp did not let through. Returns the feed per revolution commanded.
inline double AdaptiveFeedController::ramp_feed(const Input& in, double target, double error,
                                         bool sensor_ok, Reason& reason) noexcept {
  const double dt = p_.period_s;
  const double s_prog = p_.feed_programmed_mm_per_rev;
  if (target < feed_ramp_.value()) {
    feed_ramp_.reset(target);  // decreases are never delayed: they protect the tool
  } else if (contact_.in_cut() && sensor_ok && in.force > p_.load_limit &&
             target > feed_ramp_.value() + p_.feed_rate_limit_per_s * s_prog * dt) {
    // A rise the ramp limits (entering a cut, after a step down) is stopped by the present
    // sample above the limit: the per-revolution mean it regulates lags the ramp by half a
    // revolution, so it reached the limit only after the load had (e_stepped_seed004's entry
    // into its 5 mm pass: the feed rose 12 % a revolution, and the per-revolution peak was
    // 5.2 % over on Pz, 7.8 % on power). The PI is preset to the feed held, as the ramp's
    // tracking does, so it stores nothing the ramp did not let through.
    if (error > 0.0) pi_.preset(feed_ramp_.value());
    if (reason == Reason::None) reason = Reason::RateLimited;
  } else {
    bool ramped = false;
    (void)feed_ramp_.update(target, dt, ramped);
    if (ramped) {
      // Tracking anti-windup: the PI must not store what the ramp did not let through — only
      // while the error drives the integrator up. With the force above the limit but falling,
      // the target rises through the shrinking P term alone; a preset there (output at zero
      // error) dropped the next output by kp·|error|, and the feed ratcheted down to s_min in
      // steps of a few percent (found in LinuxCNC runs at an allowance step).
      if (contact_.in_cut() && error > 0.0) pi_.preset(feed_ramp_.value());
      if (reason == Reason::None) reason = Reason::RateLimited;
    }
  }
  return feed_ramp_.value();
}

// The depth of cut the speed law corrects for: the known one, else t̂ from the force model.
inline double AdaptiveFeedController::estimate_depth(const Input& in, bool known, double regulated,
                                              double s_cur) noexcept {
  const double t_hat =
      known ? in.depth_known_mm
            : std::pow(regulated / (p_.force_model_C * std::pow(s_cur, p_.force_model_y) *
                                    std::pow(in.speed_m_per_min, p_.force_model_n)),
                       1.0 / p_.force_model_x);
  depth_estimate_ = std::clamp(t_hat, 0.05 * p_.depth_planned_mm, 20.0 * p_.depth_planned_mm);
  return depth_estimate_;
}

// V_opt of seed 004 from the measured feed per revolution (computer 11), with the depth and
// tool-life corrections; the programmed speed unless the mode has the speed law and cuts.
inline double AdaptiveFeedController::optimal_speed(const Input& in, double regulated) noexcept {
  double v_opt = p_.speed_programmed_m_per_min;
  if (p_.mode != Mode::ForceFeedSpeed ||
      !(contact_.in_cut() && in.rpm > 0.0 && in.feed_rate_mm_per_min > 0.0))
    return v_opt;
  const double s_meas = std::clamp(in.feed_rate_mm_per_min / in.rpm, p_.feed_min_mm_per_rev,
                                   p_.feed_max_mm_per_rev);  // computer 11
  s_cur_filtered_ = speed_filter_.step_increment(s_cur_filtered_, s_meas);
  const double s_cur = s_cur_filtered_;
  v_opt = p_.speed_programmed_m_per_min * std::pow(p_.feed_planned_mm_per_rev / s_cur, p_.y_v);
  if (p_.y_v_ranges > 0) {  // y_v (and Cv) of the range containing each feed
    auto speed_term = [&](double s_mm) {
      const auto& r = cutting::feed_range(p_.y_v_table, p_.y_v_ranges, s_mm);
      return r.Cv / std::pow(s_mm, r.y_v);
    };
    v_opt =
        p_.speed_programmed_m_per_min * speed_term(s_cur) / speed_term(p_.feed_planned_mm_per_rev);
  }
  const bool known = std::isfinite(in.depth_known_mm) && in.depth_known_mm > 0.0;
  if (p_.depth_exponent_xv > 0.0 && (known || (regulated > 0.0 && in.speed_m_per_min > 0.0))) {
    const double depth = estimate_depth(in, known, regulated, s_cur);
    v_opt *= std::pow(p_.depth_planned_mm / depth, p_.depth_exponent_xv);
  }
  if (std::isfinite(in.speed_factor) && in.speed_factor > 0.0) v_opt *= in.speed_factor;
  return v_opt;
}

// The cutting speed aimed at: V_opt, held below what the spindle's power allows.
inline double AdaptiveFeedController::power_limited_speed(const Input& in, double v_opt,
                                                   Reason& reason) const noexcept {
  if (p_.mode != Mode::ForceFeedSpeed) return p_.speed_programmed_m_per_min;
  double v_target = v_opt;
  if (in.cut_power_W > 0.0 && in.speed_m_per_min > 0.0) {
    const double v_power = in.speed_m_per_min * p_.cut_power_max_W / in.cut_power_W;
    if (v_power < v_target) {
      v_target = v_power;
      if (reason == Reason::None) reason = Reason::SpindlePowerLimit;
    }
  }
  return v_target;
}

// Spindle speed from the current diameter seen by sensors 20 and 13, in the spindle's range.
inline double AdaptiveFeedController::spindle_rpm(const Input& in, double v_cmd,
                                           Reason& reason) const noexcept {
  double rpm = held_rpm_;
  if (in.speed_m_per_min > 0.0 && in.rpm > 0.0) rpm = in.rpm * v_cmd / in.speed_m_per_min;
  if (rpm > p_.rpm_max || rpm < p_.rpm_min) {
    rpm = std::clamp(rpm, p_.rpm_min, p_.rpm_max);
    if (reason == Reason::None) reason = Reason::SpindleSpeedLimit;
  }
  return rpm;
}

// An alarm holds the feed; the spindle keeps turning so the tool can retract safely.
inline void AdaptiveFeedController::hold_on_alarm(const Input& in, double rpm,
                                                  Output& out) noexcept {
  out.feed_per_rev_mm = 0.0;
  out.feed_rate_mm_per_min = 0.0;
  out.feed_hold = true;
  out.rpm = held_rpm_ > 0.0 ? held_rpm_ : rpm;  // the spindle keeps turning: retract safely
  // Hold the speed command with the spindle: restart from here, bumpless, after reset_alarm().
  if (in.rpm > 0.0 && in.speed_m_per_min > 0.0)
    speed_ramp_.reset(in.speed_m_per_min * out.rpm / in.rpm);
  out.speed_m_per_min = speed_ramp_.value();
  out.alarm = true;
  out.alarm_reason = alarm_reason_;
  out.reason = alarm_reason_;
}

void AdaptiveFeedController::update(const Input& in, Output& out) noexcept {
  if (!configured_) {
    out = {};
    out.feed_hold = true;
    return;
  }
  const double dt = p_.period_s;
  const PeriodTime measured = period_time(in.dt_s, dt);  // what the detectors count
  const double limit = p_.load_limit;
  const bool adaptive = p_.mode != Mode::Fixed;

  bool suspect = false;
  const Reason fault = check_sensor(in, measured, suspect);
  // Only samples the monitor accepts reach the regulation or its running average.
  const bool sensor_ok = std::isfinite(in.force) && fault == Reason::None;
  Reason reason = judge_contact(in, measured, sensor_ok);
  const double regulated = regulated_load(in, sensor_ok);

  // Feed per revolution.
  double s = p_.feed_programmed_mm_per_rev;
  if (in.feed_block && adaptive && !alarm_) {
    const double error = (limit - load_ahead(in, regulated, sensor_ok)) / limit;
    const double target = feed_target(in, error, suspect, reason);
    s = ramp_feed(in, target, error, sensor_ok, reason);
  }

  // Cutting speed, then the spindle's speed.
  const double v_opt = optimal_speed(in, regulated);
  const double v_target = power_limited_speed(in, v_opt, reason);
  bool ramped = false;
  const double v_cmd = speed_ramp_.update(v_target, dt, ramped);
  const double rpm = spindle_rpm(in, v_cmd, reason);

  out.in_cut = contact_.in_cut();
  out.force_rev = regulated;
  out.speed_opt_m_per_min = v_opt;
  out.depth_estimate_mm = depth_estimate_;
  out.speed_m_per_min = v_cmd;
  if (alarm_) {
    hold_on_alarm(in, rpm, out);
    return;
  }
  held_rpm_ = rpm;
  out.feed_per_rev_mm = s;
  out.feed_rate_mm_per_min = s * std::max(in.rpm, 0.0);
  out.rpm = rpm;
  out.feed_hold = false;
  out.alarm = false;
  out.alarm_reason = Reason::None;
  out.reason = reason;
}

}  // namespace lathectl::control
