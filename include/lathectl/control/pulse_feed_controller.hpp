#pragma once
// Feed controller of the hydraulic slide with pulsed flow regulation (seed 000), amplitude-pulse
// (AIM: the slot h is the actuator) or frequency-pulse (FIM: the pulse frequency f is).
//
// One structure for both modes (sensor → comparison → regulator → actuator):
//   P̂ = (U_D − U_0)/K_UP, low-pass filtered                        force estimate from sensor Д
//   finishing: S_cmd = S_prog                                       hold the feed
//   roughing:  S_cmd = u · S_prog, u = PI((P_set − P̂)/P_set) ∈ [u_min, 1]   hold the force,
//              never above the programmed feed
//   leakage-compensating actuator inverse, seed (3) solved for the actuator:
//     AIM: h = (S_cmd·F + K_leak·(P̂ + F_fr)/F) / Ka,  Ka = μπd·sqrt(2Δp/ρ)·Δt/T     (2)
//     FIM: f = (S_cmd·F + K_leak·(P̂ + F_fr)/F) / Kf,  Kf = μπd·h·sqrt(2Δp/ρ)·Δt     (6)
//   In finishing this is exactly h = h_0 + Δh with Δh = K_leak·ΔPy/(Ka·F), seed (4), and
//   f = f_0 + Δf with Δf = K_leak·ΔPy/(Kf·F), its FIM counterpart.
//   Beyond the seed, finishing also adds the oil compressed by a rising load, C·(dP̂/dt)/F, so
//   the feed does not dip during the force ramp (set compliance_m3_per_Pa = 0 for the seed's law).
//   Limits: slot [h_min, h_max]; frequency [f_min, f_max], duty f·Δt ≤ duty_max and the
//   converter's ramp rate (Hz/s). The PI has back-calculation anti-windup and starts bumpless
//   at u = 1 (programmed feed).
// Sensor faults (NaN, out of range, stuck): alarm latched with its reason code; in finishing the
// actuator is frozen at its last value, in roughing the feed is stopped (h = 0 / f = 0) — the
// tool must not be driven blind into a growing force. reset_alarm() clears it.
// Before the stuck alarm, a reading unchanged for SignalMonitor's suspect count (set by the
// sensor's noise and the stuck tolerance; 2 comparisons with tolerance 0) is suspect: the PI
// and the actuator may hold or fall, not rise (reason SensorSuspect) — a frozen reading never
// drives the feed up.
//
// Real-time: configure() validates and may throw; update() never allocates, throws, locks or
// logs.

#include "lathectl/control/building_blocks.hpp"
#include "lathectl/control/types.hpp"
#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::control {

class PulseFeedController {
 public:
  enum class Modulation { Amplitude, Frequency };  // AIM (slot h) or FIM (frequency f)
  enum class Mode { Finishing, Roughing };

  struct Params {
    Modulation modulation = Modulation::Amplitude;
    Mode mode = Mode::Finishing;
    double period_s = 1e-3;  // control period: update() is called every period_s
    // Design model of the regulator and slide (the controller's knowledge, may be off).
    double regulator_gain_per_m = 0.0;  // μπd·sqrt(2Δp/ρ) [m³/s per m of slot]
    double pulse_width_s = 0.01;        // Δt
    double slot_m = 40e-6;              // FIM: fixed slot h
    double frequency_Hz = 10.0;         // AIM: fixed pulse frequency 1/T
    double piston_area_m2 = 20e-4;      // F
    double leak_m3_per_s_Pa = 0.0;      // K_leak estimate
    double friction_N =
        0.0;  // friction estimate in the cylinder load (Coulomb + viscous at the feed)
    // Beyond the seed: oil volume taken up per pascal by the damper and the cylinder chamber
    // (C_d + V/B). While the load rises the oil is compressed and the slide stalls for a
    // moment whatever the leakage law; finishing adds C·dp/dt to the flow. 0 disables.
    double compliance_m3_per_Pa = 0.0;
    double rate_filter_s = 0.1;  // low-pass on the force rate used by that term
    // Programming device (ЗПУ).
    double feed_m_per_s = 1e-3;   // programmed feed rate S_prog
    double force_set_N = 1000.0;  // roughing: force setpoint
    // Sensor calibration and validity.
    double sensor_V_per_N = 1e-3;  // K_UP
    double sensor_offset_V = 0.0;  // U_0 at zero force
    double force_filter_s = 0.0;   // low-pass on the force estimate
    SignalMonitor::Params sensor_monitor;
    // Actuator limits.
    double slot_min_m = 0.0;
    double slot_max_m = 0.2e-3;
    double frequency_min_Hz = 0.0;
    double frequency_max_Hz = 50.0;
    double duty_max = 0.9;
    double frequency_ramp_Hz_per_s = 1e6;  // converter ramp
    // Roughing regulator (normalised: error as a fraction of force_set, output as a fraction
    // of the programmed feed).
    double kp = 3.0;
    double ti_s = 0.5;
    double feed_min_fraction = 0.05;
    bool operator==(const Params&) const = default;
  };

  struct Input {
    double sensor_V = 0.0;  // U_D
  };

  struct Output {
    double slot_m = 0.0;            // AIM command (FIM: the fixed slot)
    double frequency_Hz = 0.0;      // FIM command (AIM: the fixed frequency); 0 = pulses off
    double feed_cmd_m_per_s = 0.0;  // feed the controller aims at
    double force_estimate_N = 0.0;
    Reason reason = Reason::None;  // why the output is what it is
    bool alarm = false;            // latched alarm
    Reason alarm_reason = Reason::None;
  };

  void configure(const Params& p);  // throws core::ParameterError naming the Params member
  // One control period: out says what to apply and why (reason, alarm). Never allocates, throws,
  // locks or logs. Before configure() the valve stays shut (slot 0, frequency 0, feed 0).
  void update(const Input& in, Output& out) noexcept;
  // Bumpless start from a known force (e.g. the first sensor sample).
  void start(double force_N) noexcept;
  void reset_alarm() noexcept;
  // The programming device changes the operation: mode, programmed feed, force setpoint (a
  // non-finite or non-positive feed or force keeps the present one). Bumpless: the feed the
  // regulator commands does not jump with a new programmed feed. Never allocates or throws.
  void program(Mode mode, double feed_m_per_s, double force_set_N) noexcept;

  [[nodiscard]] double ka() const noexcept { return ka_; }
  [[nodiscard]] double kf() const noexcept { return kf_; }
  // Actuator value that gives feed S at load P by the design model.
  [[nodiscard]] double actuator_for(double feed_m_per_s, double load_N,
                                    double load_rate_N_per_s = 0.0) const noexcept;
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  // update()'s phases (pulse_feed_controller.cpp).
  void hold_on_alarm(Output& out) noexcept;
  void command_actuator(double a, bool suspect, Reason& reason, Output& out) noexcept;
  Params p_{};
  double ka_ = 0.0;
  double kf_ = 0.0;
  core::FirstOrderLag force_lag_;  // force_filter_s
  double force_ = 0.0;
  core::FirstOrderLag rate_lag_;  // rate_filter_s
  double force_rate_ = 0.0;
  SignalMonitor monitor_;
  PiRegulator pi_;
  RateLimiter ramp_;
  Output last_{};
  bool alarm_ = false;
  Reason alarm_reason_ = Reason::None;
  bool configured_ = false;
};

}  // namespace lathectl::control
