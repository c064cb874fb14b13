#pragma once
// Building blocks of the one controller structure the seeds share:
//   sensor → validity monitor → comparison with a programmed setpoint → regulator (PI with limits
//   and anti-windup) → rate limiter → actuator.
// All are real-time safe: configure() validates (may throw), the stepping calls never allocate,
// throw, lock or log.

#include "lathectl/control/types.hpp"

namespace lathectl::control {

// The time one step of a detector really spans. LinuxCNC's uspace servo thread hands its
// functions the nominal period even when it ran late, and then runs the periods it missed back to
// back (uspace_posix.cc: the next start advances by the period, no sleep while behind;
// hal_lib.c: funct(arg, thread->period)). Counted in nominal periods, a late stretch of real time
// shrinks (a load that fell over 12 ms, 6 ms of it in one late period, reads as a 7 ms collapse)
// and a burst of catch-up calls, which read the same sensor sample, reads as milliseconds of a
// frozen signal. The detectors that latch count the measured time instead:
//   elapsed   the measured period, at most kMaxElapsedS (a thread stopped for longer is no period):
//             windows ("within 10 ms of being loaded") — a late period only ever widens them;
//   evidence  at most twice the nominal period: timers that latch after a time spent somewhere
//             (unchanged, above the overload level) — one late period is no evidence of what the
//             signal did meanwhile, so it adds no more than two ordinary periods.
// A measured period that is not known (≤ 0 or not finite: the first call, a simulator that steps
// by the nominal period) is the nominal one.
struct PeriodTime {
  static constexpr double kMaxElapsedS = 1.0;
  double elapsed_s = 0.0;
  double evidence_s = 0.0;
};
[[nodiscard]] PeriodTime period_time(double measured_s, double nominal_s) noexcept;

// Checks one sensor sample: finite, inside [min, max], and not frozen (a real sensor with noise
// never repeats the same value for long; a stuck ADC or broken wire does).
//
// Two levels for a frozen signal:
//   suspect — the last `suspect_samples()` comparisons were all unchanged (|Δ| ≤ tolerance).
//     Cheap to be wrong about (the controller only stops raising its output), so it comes early;
//   stuck   — unchanged for stuck_time_s: latched alarm, feed hold.
// The suspect count is set by the sensor's own scale, the chance that a live sensor repeats:
// with white noise σ between samples, Δ ~ N(0, 2σ²), so P(|Δ| ≤ tol) = erf(tol/(2σ)) = p and a
// live sensor looks suspect with probability p^N. N is the smallest count with p^N ≤ 1e-6,
// at least 2 (three equal samples) and at most the stuck time's count. A quantised ADC is the
// same formula with tol = its LSB (an exact repeat of a code: give the LSB as the tolerance).
// Noise-free (σ = 0) or tol = 0 on a continuous reading (p = 0): N = 2.
// `armed = false` (the caller knows the reading may legitimately be constant, e.g. a zero-
// suppressed dynamometer reading exactly 0 with the tool in air) keeps the stuck timer at 0;
// the suspect state still applies.
class SignalMonitor {
 public:
  struct Params {
    double min = -1e300;           // lowest valid value
    double max = 1e300;            // highest valid value
    double stuck_time_s = 0.0;     // unchanged this long → stuck; 0 disables the check
    double stuck_tolerance = 0.0;  // |Δ| at or below this counts as unchanged
    double noise_sigma = 0.0;      // the sensor's noise σ between samples (sets suspect_samples)
    double period_s = 0.0;         // sample period (> 0 enables the suspect state)
    bool operator==(const Params&) const = default;
  };
  void configure(const Params& p);  // throws std::invalid_argument on min ≥ max or negative times
  // Returns Reason::None when the sample is usable, else the fault. dt in s: the time this sample
  // stands for (the stuck timer counts it; PeriodTime::evidence_s for a measured period).
  [[nodiscard]] Reason check(double value, double dt, bool armed = true) noexcept;
  void reset() noexcept;
  // The reading has not changed for suspect_samples() comparisons: do not act on it upward.
  [[nodiscard]] bool suspect() const noexcept {
    return suspect_n_ > 0 && repeats_ >= suspect_n_;
  }
  [[nodiscard]] int suspect_samples() const noexcept { return suspect_n_; }
  // Samples needed for the suspect state (rule above); 0 when the check is off.
  [[nodiscard]] static int suspect_samples_for(const Params& p) noexcept;

 private:
  Params p_{};
  double last_ = 0.0;
  double unchanged_s_ = 0.0;
  int repeats_ = 0;
  int suspect_n_ = 0;
  bool has_last_ = false;
};

// PI regulator with output limits and anti-windup by conditional integration: while the output
// is clamped and the error pushes further into the limit the integrator holds, and the
// integrator itself stays inside the output range. The output leaves a limit when the error
// changes sign — not earlier (no dip when the error merely shrinks), not later (no windup).
class PiRegulator {
 public:
  struct Params {
    double kp = 0.0;       // proportional gain [output/error]
    double ti_s = 0.0;     // integral time [s]; 0 → P only
    double out_min = 0.0;  // output lower limit
    double out_max = 1.0;  // output upper limit
  };
  void configure(const Params& p);  // throws on out_min > out_max, negative gains
  // One step; returns the clamped output. `limited` tells whether a limit was active.
  double update(double error, double dt, Reason& limited) noexcept;
  // Bumpless start: set the integrator so the next output equals `output` at zero error.
  void preset(double output) noexcept;
  // Moves the integrator by `delta` within the output range (a known drift of the output the
  // error need not build: a feed-forward into the integral).
  void shift(double delta) noexcept;
  void set_limits(double out_min, double out_max) noexcept;
  [[nodiscard]] double output() const noexcept { return out_; }

 private:
  Params p_{};
  double integral_ = 0.0;
  double out_ = 0.0;
};

// Slew-rate limiter: the output moves toward the input at most rate·dt per step.
class RateLimiter {
 public:
  void configure(double rate_per_s);  // throws on rate ≤ 0
  double update(double target, double dt, bool& limited) noexcept;
  void reset(double value) noexcept { y_ = value; }
  [[nodiscard]] double value() const noexcept { return y_; }

 private:
  double rate_ = 1.0;
  double y_ = 0.0;
};

}  // namespace lathectl::control
