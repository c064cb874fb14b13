#pragma once
// System A's machine side: what a lathe runs between the inductive sensor under the tool holder
// and the pulse regulator of the hydraulic feed slide (seed 000), in one object that the
// simulated rig (`lathectl run`) and the LinuxCNC component lathectl_slide both run.
//
//   programming device (ЗПУ)  slide on/off, mode (finishing holds the feed, roughing the
//               force) and setpoint per operation; optionally a law along the travel: a table
//               position → feed (finishing) and position → force (roughing), interpolated
//               linearly, held at its ends — the seed's "any law of h".
//   controller  PulseFeedController (AIM: the slot h, FIM: the pulse frequency f), with its
//               sensor checks (not finite, out of range, stuck, suspect).
//   roughing alarms (the reason of roughing is to save the tool):
//               overload — the force estimate above overload_factor × the force setpoint for
//               longer than overload_time_s (the regulator could not bring it down);
//               breakage — the force estimate collapses by more than breakage_drop × the
//               setpoint within breakage_window_s while the slide feeds (the tool's edge is gone).
//               Both latch and stop the feed (valve shut) until reset.
//   off         valve shut (slot 0, no pulses); the controller is not run, so a resting
//               sensor is not taken for a stuck one; at switch-on it starts bumpless from the
//               force the sensor reads.
// In an alarm the controller's own rule holds: finishing freezes the actuator at its last
// value, roughing stops the feed. A rising edge of Input::reset_alarm clears the alarm.
//
// Real-time: configure() may throw core::ParameterError naming its own parameter; update()
// never allocates, throws, locks or logs.

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "lathectl/control/collapse_detector.hpp"
#include "lathectl/control/pulse_feed_controller.hpp"
#include "lathectl/control/types.hpp"

namespace lathectl::control {

class SlideMachine {
 public:
  using Mode = PulseFeedController::Mode;
  using Modulation = PulseFeedController::Modulation;
  // The breakage window's history: the window and the present sample.
  static constexpr std::size_t kBreakageSamples = CollapseDetector::kCapacity;

  struct LawPoint {
    double position_m = 0.0;
    double value = 0.0;  // feed [m/s] or force [N]
    bool operator==(const LawPoint&) const = default;
  };
  struct Params {
    PulseFeedController::Params controller;  // mode, programmed feed and force at start
    double overload_factor = 1.5;  // × force setpoint; ∞ disables
    double overload_time_s = 0.05;
    double breakage_drop = 0.6;  // × force setpoint; ∞ disables
    double breakage_window_s = 0.01;
    // Laws along the travel (positions rising; empty: the programmed value holds).
    std::vector<LawPoint> feed_law;   // finishing: position → feed [m/s]
    std::vector<LawPoint> force_law;  // roughing: position → force setpoint [N]
    bool operator==(const Params&) const = default;
  };
  struct Input {
    double sensor_V = 0.0;  // U_D
    bool enable = true;     // the slide is on
    Mode mode = Mode::Finishing;
    double feed_m_per_s = 0.0;  // programmed feed; ≤ 0 or NaN: the present one
    double force_set_N = 0.0;   // force setpoint; ≤ 0 or NaN: the present one
    double position_m = 0.0;    // slide travel, for the laws
    bool reset_alarm = false;   // rising edge clears the alarm
  };
  struct Output {
    double slot_m = 0.0;        // AIM: eccentric's slot command; FIM: the fixed slot
    double frequency_Hz = 0.0;  // pulse frequency; 0 = no pulses
    bool pulses = false;        // the valve pulses (false: held shut)
    double feed_cmd_m_per_s = 0.0;
    double force_estimate_N = 0.0;
    double feed_set_m_per_s = 0.0;  // the programmed feed in force (law included)
    double force_set_N = 0.0;       // the force setpoint in force (law included)
    Mode mode = Mode::Finishing;
    bool enabled = false;
    Reason reason = Reason::None;
    bool alarm = false;
    Reason alarm_reason = Reason::None;
  };

  void configure(const Params& p);  // throws core::ParameterError
  // Starts (bumpless) from a known force, enabled, with the configured program.
  void start(double force_N) noexcept;
  void update(const Input& in) noexcept;
  [[nodiscard]] const Output& output() const noexcept { return out_; }
  [[nodiscard]] const PulseFeedController& controller() const noexcept { return ctl_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // A law's value at a position (linear, held at the ends); NaN for an empty law.
  [[nodiscard]] static double law_at(const std::vector<LawPoint>& law, double x) noexcept;

 private:
  void latch(Reason r) noexcept;
  // update()'s phases (slide_machine.cpp).
  void switch_off() noexcept;
  void program(const Input& in) noexcept;
  void write_outputs(double est) noexcept;
  Params p_{};
  PulseFeedController ctl_;
  PulseFeedController::Output co_{};
  Output out_{};
  bool configured_ = false;
  bool enabled_ = true;
  bool last_reset_ = false;
  bool alarm_ = false;  // the machine's own (overload, breakage)
  Reason alarm_reason_ = Reason::None;
  long long over_n_ = 0;        // control periods above the overload limit in a row
  long long over_limit_n_ = 0;  // overload_time_s in control periods
  CollapseDetector collapse_;  // the force estimate over the breakage window
  std::size_t hist_n_ = 1;     // samples in the breakage window
};

}  // namespace lathectl::control
