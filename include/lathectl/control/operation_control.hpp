#pragma once
// What a shop's adaptive control needs around the control law (Heidenhain AFC, Caron TMAC), for
// the LinuxCNC component lathectl_adaptive:
//
//   IdleTare        the spindle drive's idle power P_idle(n) = p0 + p1·n + p2·n² (seed 001's
//                   law, drives::idle_power_W) learned from the drive's power pin while the tool
//                   is out of the cut at a steady speed, so that P_cut = P_drive − P_idle(n) is
//                   the load sensor a lathe without a dynamometer has. Speed bins hold a running
//                   mean (time constant tau_s: warm-up drift is followed) and the law is fitted by
//                   least squares over the bins that have data (every speed counts once, however
//                   long the machine stood there).
//   TeachIn         the reference load of a teach cut: the mean of the load over the steady cut,
//                   whole revolutions only, without the entry (at least settle_revs revolutions,
//                   and until a revolution's mean is within steady_tol of the one before) and
//                   without the exit (the last revolutions before the tool left the cut: held
//                   back kHeld revolutions, taken at the end up to the first whose mean leaves
//                   the steady mean by more than steady_tol, and never the last whole one).
//   OperationStats  one operation's record for the log: the mean load in cut, the peak of its
//                   per-revolution mean (PerRevolutionMean, whole revolutions only), the
//                   adaptive feed factor (min and mean) and the time in cut.
//   check_operation the per-operation settings a program or a tool table gives, against the
//                   machine's rating: a code naming what is wrong, never a silently used value.
//   split_feed_override  a feed above the program's: the net override (operator's knob times
//                   the controller's factor, at most the machine's maximum) split into motion's
//                   feed scale (the ceiling, raised through halui) and motion.adaptive-feed in
//                   [0, 1] (every decrease, in the servo period it is computed).
//
// Real-time: update()/sample()/check never allocate, throw, lock or log.

#include <array>
#include <cstddef>
#include <cstdint>

#include "lathectl/control/collapse_detector.hpp"
#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::control {

class IdleTare {
 public:
  static constexpr std::size_t kBins = 32;
  struct Params {
    bool operator==(const Params&) const = default;
    double rpm_max = 4000.0;      // the speed range the bins cover [0, rpm_max]
    double rpm_min = 30.0;        // below this the spindle is not "running" (nothing learned)
    double tau_s = 3.0;           // running-mean time constant of a bin
    double steady_rpm_per_s = 20.0;  // |dn/dt| above this: the drive accelerates, not idle
    double settle_s = 0.2;        // after a speed change, wait this long before learning
  };
  void configure(const Params& p);  // throws std::invalid_argument
  // One sample of the drive's power at speed rpm; `air` when the tool is out of the cut.
  void update(double rpm, double drive_power_W, double dt, bool air) noexcept;
  // P_idle at rpm from the fitted law; NaN until one bin has data.
  [[nodiscard]] double idle_W(double rpm) const noexcept;
  [[nodiscard]] bool ready() const noexcept { return populated_ >= 3; }
  // Whether the law is known at rpm: a learned bin within 10 % (or one bin width) of it, or rpm
  // inside the span of three or more learned bins. Elsewhere the fit would extrapolate.
  [[nodiscard]] bool covers(double rpm) const noexcept;
  [[nodiscard]] std::size_t bins_learned() const noexcept { return populated_; }
  // The speed of the learned bin nearest rpm (NaN before any): where a fit of fewer than three
  // bins (a constant or a line) is right.
  [[nodiscard]] double nearest_bin_rpm(double rpm) const noexcept;
  // The fitted law's coefficients p0 [W], p1 [W/rpm], p2 [W/rpm²].
  [[nodiscard]] std::array<double, 3> coefficients() const noexcept { return c_; }

 private:
  void fit() noexcept;
  void learn(double rpm, double power_W, double dt) noexcept;
  // Samples not yet learned: one is learned once the speed has stayed steady settle_s after it
  // (or the tool entered a cut at that speed), so the drive's power at the start of a speed
  // change (its torque rises before the speed moves) never is. A ring, allocated with the object.
  static constexpr std::size_t kPending = 1024;
  std::array<double, kPending> pend_rpm_{}, pend_power_{};
  std::size_t pend_head_ = 0, pend_count_ = 0;
  Params p_{};
  std::array<double, kBins> power_{};
  std::array<double, kBins> rpm_{};
  std::array<double, kBins> weight_s_{};
  std::array<double, 3> c_{};
  std::size_t populated_ = 0;
  double last_rpm_ = 0.0;
  double steady_s_ = 0.0;
  bool dirty_ = false;
};

class TeachIn {
 public:
  struct Params {
    bool operator==(const Params&) const = default;
    double settle_revs = 3.0;   // entry transient: revolutions in cut not taken, at least
    double steady_tol = 0.02;   // ... and until consecutive revolutions' means agree this well
    double min_revs = 3.0;      // fewer whole steady revolutions: no reference
  };
  void configure(const Params& p) noexcept { p_ = p; }
  void start() noexcept;
  // One control period; returns true once, when the cut has ended with a reference.
  bool sample(double load, double rpm, double dt, bool in_cut) noexcept;
  [[nodiscard]] bool running() const noexcept { return running_; }
  [[nodiscard]] double reference() const noexcept { return reference_; }
  [[nodiscard]] double revolutions() const noexcept { return revs_; }

 private:
  Params p_{};
  static constexpr std::size_t kHeld = 16;
  void take(double sum, double n) noexcept;
  bool running_ = false;
  bool cutting_ = false;
  bool steady_ = false;
  double last_rev_mean_ = 0.0;  // while settling
  double t_in_revs_ = 0.0;  // revolutions since contact
  double rev_phase_ = 0.0;  // of the revolution being filled
  double cur_sum_ = 0.0, cur_n_ = 0.0;  // the revolution being filled
  std::array<double, kHeld> held_sum_{}, held_n_{};  // whole revolutions not yet taken (a ring)
  std::size_t held_head_ = 0, held_count_ = 0;
  double sum_ = 0.0, n_ = 0.0, revs_ = 0.0;
  double reference_ = 0.0;
};

class OperationStats {
 public:
  void reset() noexcept { *this = OperationStats{}; }
  // One control period: the load, its per-revolution mean and whether that spans a whole
  // revolution, the adaptive feed factor, in a cut (feed block, tool in contact).
  void sample(double load, double load_rev, bool whole_rev, double feed_factor, double dt,
              bool in_cut) noexcept;
  [[nodiscard]] double mean_load() const noexcept { return t_cut_ > 0.0 ? load_int_ / t_cut_ : 0.0; }
  [[nodiscard]] double peak_load() const noexcept { return rev_peak_; }
  [[nodiscard]] double feed_min() const noexcept { return t_cut_ > 0.0 ? feed_min_ : 1.0; }
  [[nodiscard]] double feed_mean() const noexcept {
    return t_cut_ > 0.0 ? feed_int_ / t_cut_ : 1.0;
  }
  [[nodiscard]] double time_in_cut_s() const noexcept { return t_cut_; }
  [[nodiscard]] double time_s() const noexcept { return t_; }

 private:
  double t_ = 0.0, t_cut_ = 0.0;
  double feed_min_ = 1e300, feed_int_ = 0.0;
  double load_int_ = 0.0, rev_peak_ = 0.0;
};

// A tool's row of the per-tool limits table (lathectl_adaptive's tools= file; AFC keeps these in
// the tool table): the defaults a program that sets nothing runs with, and the overload levels
// as percentages of the reference.
struct ToolLimits {
  bool operator==(const ToolLimits&) const = default;
  int number = 0;
  double limit = 0.0;  // 0: the scenario's
  double feed_min_mm_per_rev = 0.0;
  double feed_max_mm_per_rev = 0.0;
  bool adaptive = true;
  double reference_pct = 100.0;
  double warn_pct = 0.0;  // 0: off
  double hold_pct = 0.0;
};

// Tool breakage by load collapse that knows the path: a load that falls from above half the limit
// to below the air threshold within `window_s` is a broken tool only while the stock model still
// predicts engagement (its depth of cut at least `keep` of what it was while loaded). A
// programmed exit (a G70 contour leaving the material along an arc) takes the predicted depth
// down with the load. Sampled every servo period: the stop comes in the period the load falls.
class PathBreakage {
 public:
  struct Params {
    bool operator==(const Params&) const = default;
    double window_s = 0.01;   // the controller's breakage_drop_window_s
    double air = 0.1;         // air threshold, fraction of the limit
    double keep = 0.5;        // predicted depth still ≥ keep × the loaded one: material is there
    double min_depth_mm = 0.05;
  };
  void configure(const Params& p) noexcept {
    p_ = p;
    collapse_.configure(p.window_s);
    reset();
  }
  void reset() noexcept {
    collapse_.reset();
    depth_high_ = 0.0;
  }
  // A period whose load cannot be judged (AdaptiveMachine: a power reading that cannot be
  // separated from the spindle's acceleration): time passes, nothing is judged, so a collapse
  // after it is measured from the last load that could be.
  void skip(double dt) noexcept { collapse_.pass(dt); }
  // True in the period a collapse with engagement predicted is seen. dt: the time since the last
  // call as measured (PeriodTime::elapsed_s), never the thread's nominal period: after a late
  // period the fall of the load took that much longer than the number of calls says.
  bool update(double load, double limit, double predicted_depth_mm, double dt) noexcept {
    return update(load, limit, predicted_depth_mm, predicted_depth_mm, dt);
  }
  // With what the model cannot know: the depth it predicts (nominal) and the least the real blank
  // can give there (guaranteed: less its eccentricity on the blank's surface, less its random
  // allowance). A collapse is a broken tool only where the guaranteed depth is still ≥ keep × the
  // nominal one while loaded: an eccentric blank cut shallower than its eccentricity is an
  // interrupted cut, whose load falls to air once a revolution with a sound tool.
  bool update(double load, double limit, double nominal_depth_mm, double guaranteed_depth_mm,
              double dt) noexcept;

 private:
  Params p_{};
  CollapseDetector collapse_;  // the loads above half the limit, within window_s
  double depth_high_ = 0.0;  // predicted depth while the load was above half the limit
};

// What is wrong with a per-operation setting (0: nothing). The component's bad-code pin.
enum class SettingError : std::int32_t {
  None = 0,
  LimitNotFinite = 1,
  LimitNegative = 2,
  LimitAboveRating = 3,
  FeedBounds = 4,  // feed_min ≤ 0, feed_max ≤ feed_min, not finite, or above the rating
  Mode = 5,        // not one of the mode codes
  Percentage = 6,  // a percentage of the taught reference outside (0, max]
  NotTaught = 7,   // control at a percentage of a reference this tool/operation has not taught
};

struct OperationRating {
  bool operator==(const OperationRating&) const = default;
  double limit_max = 0.0;     // the machine's rating in the sensor's unit (N or W)
  double feed_max_mm_per_rev = 0.0;
  double percent_max = 200.0;  // of a taught reference
};

// A limit, feed bounds (0 means "not set": the caller's default applies, so only negative, NaN
// and too-large values are errors), checked against the rating.
[[nodiscard]] SettingError check_limit(double limit, const OperationRating& r) noexcept;
[[nodiscard]] SettingError check_feeds(double feed_min, double feed_max,
                                       const OperationRating& r) noexcept;

// Above the programmed feed on LinuxCNC. motion's net feed scale is feed_scale × adaptive-feed
// (src/emc/motion/control.c). LinuxCNC up to 2.9 clips motion.adaptive-feed to [-1, 1] (since
// commit 062589ef05, Oct 2024, to ±MAX_FEED_OVERRIDE), so a factor above 1 must go through
// feed_scale: EMC_TRAJ_SET_SCALE, which halui.feed-override sends, clipped by halui to
// [0, [DISPLAY]MAX_FEED_OVERRIDE] — the value the trajectory planner sizes its blends for. That
// path is slow (halui's 20 ms loop, then task, then motion; its status comes back as late), so
// it only ever carries a ceiling; the fast path, adaptive-feed, carries every decrease in the
// period it is computed:
//
//   net      = min(knob × factor, max)       feed moves (knob alone outside them)
//   scale    = max(scale before, net, knob)  in a feed move: never lowered there (a lower scale
//                                             reaches motion ~0.1-0.2 s before its status does,
//                                             and the divisor below would then dip the feed)
//            = knob                           outside feed moves (rapids are scaled by the rapid
//                                             override, not this), so the next move starts
//                                             from the operator's value
//   adaptive = min(1, net / max(scale, scale_in_motion))   feed moves; 1 outside
//
// With scale_in_motion the feed scale motion reports (halui.feed-override.value, which lags
// motion), motion's product is never above net while a new scale is on its way (lowered: the
// old, higher one divides; raised: the new one divides, the old one multiplies). The operator's
// knob is the one way to the feed scale besides this (one owner), and its decrease takes effect
// in the same control period through adaptive-feed.
struct FeedOverride {
  double net = 1.0;       // the override of the program's feed wanted now
  double scale = 1.0;     // motion's feed scale to command (halui.feed-override)
  double adaptive = 1.0;  // motion.adaptive-feed, in [0, 1]
};
// factor: the controller's feed over the program's (≥ 0); knob: the operator's override, at most
// max; max: MAX_FEED_OVERRIDE; step: the feed scale's resolution (halui's counts × scale: the
// scale is rounded up to it, never above max); scale_before: the scale this returned last. A NaN
// or negative knob or factor counts as 0 (the feed stops); a max that is not positive and finite
// counts as 1 (the program's feed).
[[nodiscard]] FeedOverride split_feed_override(double factor, double knob, double max, double step,
                                               double scale_before, double scale_in_motion,
                                               bool feed_move) noexcept;

}  // namespace lathectl::control
