#pragma once
// Adaptive lathe control of seed 004 and its prior art, in one structure (drawing numbers):
//
//   force setter 6 ─→ comparator 5 ←─ sensor 4 (force parameter: Pz, Py or cutting power)
//        → feed regulator 7 (PI on the normalised error, anti-windup) → limiter 8:
//          s_min ≤ s ≤ s_max (setters 9, 10), s = F/n from feed-rate sensor 12 and speed
//          sensor 13 (computer 11) → feed drive 1, as a feed-rate command s·n
//   seed 004 adds: divider 14 (S_p / S_cur), power block 16 (^y_v), multiplier 17 (× V_p):
//          V_opt = V_p · (S_p / S_cur)^{y_v}
//        → comparator 19 ←─ cutting-speed sensor 20 → spindle regulator: n = n_meas·V_cmd/V_meas
//          (the current diameter from sensors 20 and 13), clamped to the spindle's speed range
//          and to its power: V_cmd ≤ V_meas · P_max / P_cut.
//
// Modes: Fixed (programmed feed and speed, the baseline), ForceFeed (prior art: force held by
// feed, speed constant), ForceFeedSpeed (seed 004: plus the speed law).
//
// What a machinist demands of a real one, beyond the drawing:
//   - air-cut detection: force below air_threshold·limit for air_time_s → air feed (may exceed
//     the programmed feed: "feed up in air"); on contact (force above the threshold) the feed
//     drops at once to the entry feed and the PI is preset there, then rises at its rate limit
//     (bumpless engagement: the first revolution's chip already carries the air feed);
//   - outside feed blocks (rapids) the controller is inactive and restarts bumpless;
//   - feed never above the programmed value in cut unless allow_above_programmed;
//   - rate limits on feed per revolution and on cutting speed;
//   - overload alarm: force above (1 + overload_margin)·limit for overload_time_s while the feed
//     is already at s_min → feed hold;
//   - tool-breakage alarm: force spike above breakage_spike·limit, or a drop from above half the
//     limit to below the air threshold within breakage_drop_window_s inside a feed block →
//     feed hold;
//   - sensor lost, stuck, NaN or out of range → feed hold, alarm, reason code;
//   - a frozen reading never drives the feed up: after SignalMonitor's suspect count of
//     unchanged samples (2 for a continuous noisy reading: three equal samples, 4 ms at 2 ms)
//     the feed holds or falls (reason SensorSuspect), long before the stuck alarm
//     (sensor_stuck_ms, 100 ms by default);
//   - a constant reading at or below the air threshold with the tool out of the cut is air (a
//     zero-suppressed dynamometer reads exactly 0 there), not a stuck sensor: the stuck timer runs
//     only in a cut or above the air threshold, never in rapids. While such a reading stays
//     constant the feed is not raised either (no feed-up in air on a signal that cannot show the
//     contact; the programmed feed holds), and the first contact moves the reading;
//   - every limit, hold or alarm sets a Reason; alarms latch until reset_alarm();
//   - the detectors count the measured period (Input::dt_s, PeriodTime), not the nominal one: a
//     servo thread that ran late never turns a slow fall of the load into a breakage, nor the
//     catch-up calls after it (the same sample, again and again) into a stuck sensor.
// Real-time: configure() validates and may throw; update() never allocates, throws, locks or logs.

#include <array>
#include <vector>

#include "lathectl/control/building_blocks.hpp"
#include "lathectl/control/collapse_detector.hpp"
#include "lathectl/control/contact.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "lathectl/control/types.hpp"
#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::control {

class AdaptiveFeedController {
 public:
  enum class Mode { Fixed, ForceFeed, ForceFeedSpeed };

  struct Params {
    bool operator==(const Params&) const = default;
    Mode mode = Mode::ForceFeedSpeed;
    double period_s = 0.002;                  // control period
    // Setter 6: the limit on what sensor 4 reads, in its unit: N for Pz or Py, W when the load is
    // the spindle's cutting power (the scenario's force_limit_N or cut_power_limit_kW).
    double load_limit = 1000.0;
    double feed_programmed_mm_per_rev = 0.4;  // programmed feed (fixed mode's feed)
    double feed_min_mm_per_rev = 0.05;        // setter 10
    double feed_max_mm_per_rev = 0.8;         // setter 9
    bool allow_above_programmed = false;
    double air_feed_mm_per_rev = 0.4;     // feed while in air
    double entry_feed_mm_per_rev = 0.05;  // feed the tool drops to on contact (bumpless entry)
    double speed_programmed_m_per_min = 150.0;  // V_p, setter 18 (fixed and prior art: V)
    double feed_planned_mm_per_rev = 0.4;       // S_p, setter 15
    double y_v = 0.35;                          // exponent of feed in the tool-life formula
    // y_v from the handbook's feed ranges: the same table as the tool-life law,
    // {s_max, Cv, y_v} per range. Given (y_v_ranges > 0), the speed law is the seed's with y_v
    // (and Cv) of the range that contains each feed — equal tool life at equal depth:
    //   V_opt = V_p · [Cv(S)/S^{y_v(S)}] / [Cv(S_p)/S_p^{y_v(S_p)}]
    // which is V_p·(S_p/S)^{y_v} when S and S_p share a range. 0 ranges: the single y_v above.
    struct YvRange {
      bool operator==(const YvRange&) const = default;
      double feed_max_mm_per_rev = 1e9;
      double Cv = 1.0;
      double y_v = 0.35;
    };
    std::array<YvRange, 3> y_v_table{};
    int y_v_ranges = 0;
    // Low-pass on S_cur = F/n (computer 11) before the speed law. Unfiltered, a spindle speed-up
    // lowers the measured F/n (the feed axis lags), which raises V_opt again: the loop hunts.
    double speed_law_filter_s = 1.0;
    // Beyond the seed: also correct the speed for the depth of cut, V·(t_p/t̂)^{x_v}, with t̂
    // estimated from the force by the design model F = C·t^x·s^y·V^n (only for a force sensor).
    // The seed's law keeps tool life at plan only at the planned depth; this keeps it for any
    // depth. Off (seed law) when depth_exponent_xv = 0.
    double depth_exponent_xv = 0.0;  // x_v of the tool-life formula; 0 = seed law
    double depth_planned_mm = 3.0;   // t_p
    double force_model_C = 0.0;      // F = C·t^x·s^y·V^n (N; mm, mm/rev, m/min)
    double force_model_x = 1.0;
    double force_model_y = 0.75;
    double force_model_n = -0.15;
    double rpm_min = 10.0;
    double rpm_max = 4000.0;
    double cut_power_max_W = 1e9;  // spindle power available for cutting
    double kp = 0.5;  // PI on (limit − force)/limit → feed [fraction of programmed]
    double ti_s = 0.1;
    double feed_rate_limit_per_s = 0.5;  // max |ds/dt| as a fraction of the programmed feed per s
    double speed_rate_limit_m_per_min_per_s = 100.0;
    double air_threshold = 0.1;  // fraction of load_limit
    double air_time_s = 0.05;
    double overload_margin = 0.3;
    double overload_time_s = 0.2;
    double breakage_spike = 2.5;  // fraction of load_limit
    double breakage_drop_window_s = 0.01;  // 0: no collapse detector
    // Regulate the force averaged over one spindle revolution (window from the measured speed):
    // the feed reaches the chip only over a revolution, so within-revolution swings (runout of
    // an eccentric blank) are not the feed's to fight; the regulator compares the mean one
    // revolution ahead while it rises (its trend from the load at the same angle a revolution
    // ago) with the limit. Contact, air and breakage use the raw signal.
    bool average_per_revolution = true;
    SignalMonitor::Params sensor_monitor;
  };

  struct Input {
    double force = 0.0;                 // sensor 4 (N or W)
    double feed_rate_mm_per_min = 0.0;  // sensor 12
    double rpm = 0.0;                   // sensor 13
    double speed_m_per_min = 0.0;       // sensor 20 (V = π·D·n)
    double cut_power_W = 0.0;           // spindle power minus idle power at this speed
    bool feed_block = true;             // a cutting (G1) block is active
    // The time since the last update() as measured [s] (LinuxCNC: rtapi_get_time() differences);
    // 0: the nominal period_s. The latching detectors (breakage window, stuck sensor, overload)
    // count it (PeriodTime), so a late servo period reads neither as a collapse nor as a stall;
    // the regulator and ramps keep the nominal period.
    double dt_s = 0.0;
    // A ceiling on the feed per revolution from outside (AdaptiveMachine's feed-forward from the
    // stock model: what a known rise in the depth ahead takes at the limit) [mm/rev]; ≤ 0 or
    // not finite: none. Never below s_min; in a cut the regulator restarts from it.
    double feed_ceiling_mm_per_rev = 0.0;
    // A drift of the feed the limit takes, known from outside (AdaptiveMachine: the specific
    // force rising, a hard spot coming into the chip) [mm/rev per s]; added to the regulator's
    // integral in a cut, so it follows the drift without the error a ramp otherwise takes.
    // 0 or not finite: none.
    double feed_drift_mm_per_rev_per_s = 0.0;
    // The depth of cut when it is known (AdaptiveMachine's stock model: the last revolution's
    // chip) [mm]; > 0: the depth-corrected law takes it instead of estimating t̂ from the force,
    // which reads a harder spot as a deeper cut. ≤ 0 or not finite: estimated as before.
    double depth_known_mm = 0.0;
    // A factor on V_opt from outside (AdaptiveMachine's tool-life law: K_mv of the hardness the
    // cut has shown); ≤ 0 or not finite: 1.
    double speed_factor = 1.0;
    // The load reading cannot be separated now (AdaptiveMachine: the spindle's acceleration
    // power with an inertia not yet learned): in a cut the feed may fall but not rise, as for a
    // suspect reading, with reason PowerAccelerationUnknown.
    bool reading_unusable = false;
  };

  struct Output {
    double feed_per_rev_mm = 0.0;       // commanded feed per revolution (0 on feed hold)
    double feed_rate_mm_per_min = 0.0;  // to the feed drive: s·n_meas
    double speed_m_per_min = 0.0;       // commanded cutting speed
    double rpm = 0.0;                   // to the spindle drive
    double speed_opt_m_per_min = 0.0;   // V_opt by seed 004 (for the record)
    double depth_estimate_mm = 0.0;     // t̂ (depth-corrected law only)
    // The force regulated: its mean over the last revolution since the cut began
    // (average_per_revolution), else the accepted sample.
    double force_rev = 0.0;
    bool in_cut = false;
    bool feed_hold = false;
    Reason reason = Reason::None;  // why the output is what it is
    bool alarm = false;
    Reason alarm_reason = Reason::None;
  };

  void configure(const Params& p);  // throws std::invalid_argument
  // One control period. Never allocates, throws, locks or logs. Before configure(): feed hold.
  // Everything it decides is in the Output: the feed, the speed, the reason and the alarm.
  void update(const Input& in, Output& out) noexcept;
  void reset_alarm() noexcept;
  [[nodiscard]] bool configured() const noexcept { return configured_; }
  // Per-operation settings (an NC block, a tool change: lathectl_adaptive) without re-allocating:
  // the limit, the feed bounds (the configured programmed and entry feeds are clamped into them)
  // and adaptive on/off (off: the configured mode's Fixed baseline). Returns false and changes
  // nothing unless 0 < limit and 0 < s_min < s_max, all finite.
  [[nodiscard]] bool set_operation(double load_limit, double feed_min_mm_per_rev,
                                   double feed_max_mm_per_rev, bool adaptive) noexcept;
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  double feed_ceiling() const noexcept;
  // update()'s phases, in the order they run (adaptive_feed_controller.cpp says what each decides).
  void raise(Reason r) noexcept;
  Reason check_sensor(const Input& in, const PeriodTime& measured, bool& suspect) noexcept;
  Reason judge_contact(const Input& in, const PeriodTime& measured, bool sensor_ok) noexcept;
  double regulated_load(const Input& in, bool sensor_ok) noexcept;
  double load_ahead(const Input& in, double regulated, bool sensor_ok) noexcept;
  double feed_target(const Input& in, double error, bool suspect, Reason& reason) noexcept;
  [[nodiscard]] double regulator_dt(const Input& in) const noexcept;
  double ramp_feed(const Input& in, double target, double error, bool sensor_ok,
                   Reason& reason) noexcept;
  double estimate_depth(const Input& in, bool known, double regulated, double s_cur) noexcept;
  double optimal_speed(const Input& in, double regulated) noexcept;
  double power_limited_speed(const Input& in, double v_opt, Reason& reason) const noexcept;
  double spindle_rpm(const Input& in, double v_cmd, Reason& reason) const noexcept;
  void hold_on_alarm(const Input& in, double rpm, Output& out) noexcept;
  Params p_{};
  Params base_{};  // as configured (set_operation changes p_ only)
  bool configured_ = false;
  SignalMonitor monitor_;
  PiRegulator pi_;
  RateLimiter feed_ramp_;
  RateLimiter speed_ramp_;
  ContactDetector contact_;
  double over_s_ = 0.0;
  CollapseDetector collapse_;  // the samples above half the limit, within breakage_drop_window_s
  bool alarm_ = false;
  Reason alarm_reason_ = Reason::None;
  double held_rpm_ = 0.0;
  double depth_estimate_ = 0.0;
  double s_cur_filtered_ = 0.0;
  core::FirstOrderLag speed_filter_;  // of the measured feed, speed_law_filter_s
  PerRevolutionMean rev_mean_;  // of the accepted readings, since the cut began
  PerRevolutionMean feed_rev_;  // the feed commanded, with rev_mean_'s samples: the chip h(t)
  PerRevolutionMean chip_rev_;  // h(t) as pushed, for h(t − T) (load_ahead)
  double trend_ = 0.0;  // L(t) − L(t − T)·(h(t)/h(t − T))^y, low-passed over T/4 (load_ahead)
  core::FirstOrderLag trend_lag_;  // over T/4 at trend_lag_rpm_
  double trend_lag_rpm_ = -1.0;
};

}  // namespace lathectl::control
