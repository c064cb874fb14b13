// AdaptiveMachine's power sensor: the cutting power from the spindle drive's power, less its
// idle power (the tare) and the power that accelerates the spindle (J·ω·dω/dt, with J learned in
// air). The rest of the class is in adaptive_machine.cpp.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "lathectl/control/adaptive_machine.hpp"

namespace lathectl::control {

// The power at the spindle beyond its friction (the cut and J·ω·dω/dt) from what the drive draws
// above its air power A(n) = P_idle(n) + b·ω²/η (the tare's, or the prior's law). The drive draws
// D(m) + P_idle for the shaft's power m = P_cut + J·ω·dω/dt + b·ω² (drawn_power_W: m/η motoring,
// η·m braking), so m = D⁻¹(drawn + b·ω²/η) and what is left of it past the friction is
//   motoring (drawn + b·ω²/η ≥ 0):  η·drawn                 (the friction cancels exactly)
//   braking  (drawn + b·ω²/η < 0):   (drawn + b·ω²/η)/η − b·ω²
// Taking drawn/η when braking, as before, read the cut b·ω²·(1/η² − 1) low: a forged shaft's
// spindle slowing by 300 rpm/s under the speed law at 2200 rpm (2 kg·m², 15 kW of inertia power
// against 6.2 kW of cut) returns its energy through the drive, and the cut read 3-8 % low while
// it was 12.6 % over its limit (issue 47). b is the prior's viscous friction (a tare learns only
// the sum A(n)).
double AdaptiveMachine::shaft_power(double drawn, double rpm) const noexcept {
  const double eta = p_.spindle.efficiency;
  const double w = std::abs(rpm) * 2.0 * std::numbers::pi / 60.0;
  const double friction = p_.spindle.viscous_N_m_s * w * w;
  const double shaft_drawn = drawn + friction / eta;
  return shaft_drawn >= 0.0 ? drawn * eta : shaft_drawn / eta - friction;
}

// The load sensor 4 gives the controller, and with the power sensor the cutting power at the
// spindle: η·(P_drive − P_idle(n)) − J·ω·dω/dt.
double AdaptiveMachine::measured_load(const Input& in, bool feed_move, double rpm, double dt,
                                      Output& out, bool& sensing) noexcept {
  sensing = true;
  if (!p_.power_sensor) return in.force;
  // Outside feed moves (rapids, dwells, tool changes) the drive draws its idle power only.
  tare_.update(rpm, in.spindle_power_W, dt, !feed_move);
  const bool learned = tare_.covers(rpm);
  // Until the tare has learned this speed: what the drive draws in air by its parameters (the
  // idle law and viscous friction; without the friction a prior-art run at a steady 1750 rpm
  // read 336 W of cutting in air and took it for contact).
  // With fewer than three bins the tare's fit is a constant or a line, which knows nothing of the
  // law's slope and curvature: 10 % from its one bin (2340 rpm against 2490) a constant read the
  // air power 300 W high, and a braking cut (over η) 6 % low (issue 47's forged shafts). Then the
  // prior's law runs through the nearest bin: P_air(n) + (tare − P_air) at that bin.
  double idle = drives::air_power_W(p_.spindle, rpm);
  if (learned && tare_.ready()) {
    idle = tare_.idle_W(rpm);
  } else if (learned) {
    const double nb = tare_.nearest_bin_rpm(rpm);
    idle += tare_.idle_W(nb) - drives::air_power_W(p_.spindle, nb);
  }
  out.idle_power_W = std::isfinite(idle) ? idle : 0.0;
  out.idle_law = tare_.coefficients();
  out.tare_ready = learned;
  out.acceleration_power_W = accel_lagged_W_;  // (acceleration_power(), every servo period)
  // The mechanical power at the spindle: a motoring drive draws it over η, a braking one returns
  // η of it (regeneration).
  const double drawn = in.spindle_power_W - out.idle_power_W;
  const double mech_net = shaft_power(drawn, rpm);
  // The inertia, from speed changes in air where the tare knows the idle power: the mechanical
  // power there is J·ω·dω/dt alone (least squares through the origin).
  if (p_.learn_inertia && !feed_move && learned && std::isfinite(drawn) &&
      std::abs(wdw_lagged_) > 20.0 * std::abs(rpm) * 2.0 * std::numbers::pi / 60.0) {
    j_sxy_ += wdw_lagged_ * mech_net;
    j_sxx_ += wdw_lagged_ * wdw_lagged_;
    j_seen_s_ += dt;
    if (j_seen_s_ >= p_.learn_inertia_min_s && j_sxx_ > 0.0 && j_sxy_ > 0.0) {
      inertia_ = j_sxy_ / j_sxx_;
      j_ready_ = true;
    }
  }
  out.inertia_kg_m2 = inertia_;
  out.inertia_learned = j_ready_;
  double load = mech_net - accel_lagged_W_;
  // In a feed move, while the inertia is still the prior of one to be learned, J·ω·dω/dt is
  // known only to its own size (a prior of 0.5 for a true 2 kg·m² leaves 3/4 of it in the
  // reading: braking, the cut reads that much low and the regulator would raise the feed).
  // Where it is above 5 % of the limit (the band the regulator holds) the reading cannot be
  // separated: it is held — the feed may fall, not rise — until a revolution after it is small
  // again, when the per-revolution mean no longer holds it. A given inertia, or a learned one,
  // is trusted.
  if (feed_move && p_.learn_inertia && !j_ready_ &&
      std::abs(accel_lagged_W_) > 0.05 * applied_.limit)
    inseparable_left_s_ = 60.0 / std::max(rpm, 1.0);
  else
    inseparable_left_s_ = std::max(0.0, inseparable_left_s_ - dt);
  sensing = !(feed_move && inseparable_left_s_ > 0.0);
  if (!feed_move) {
    // Outside feed moves nothing is cut: what is left is not a load, and not a sensor fault
    // either — a speed change in air before the inertia is learned (or with a wrong one) leaves
    // J·ω·dω/dt of either sign, tens of kW, and latched sensor_out_of_range. A reading that is
    // not a number still reaches the monitor; the drive's own reading is not range-checked
    // there: a run-up draws more than twice the rating for a moment (30 kW on the 15 kW sample
    // machine's idle sweep, which latched the alarm when it was).
    if (!std::isfinite(in.spindle_power_W)) return in.spindle_power_W;
    load = std::clamp(load, 0.0, ctl_.params().sensor_monitor.max);
  }
  return load;
}

// The power that accelerates the spindle, J·ω·dω/dt [W], from the measured speed over the last
// servo period (the nearest in time to the power reading), lagged as the power meter lags.
void AdaptiveMachine::acceleration_power(double rpm, double dt, double nominal_s) noexcept {
  // dω/dt as a difference over at least one nominal period of measured time: on time, the last
  // period's, as before. Under a loaded LinuxCNC a late period is followed by short catch-up
  // calls, each with one period's speed change over a fraction of a period: a braking spindle
  // read 29 kW for one sample (sensor_out_of_range in the shop session's idle sweep). Then the
  // difference reaches back over the late period.
  const double omega = std::abs(rpm) * 2.0 * std::numbers::pi / 60.0;
  if (!std::isfinite(omega)) {
    accel_n_ = 0;
  } else {
    accel_now_s_ += dt > 0.0 ? dt : nominal_s;
    double accel = 0.0;
    if (accel_n_ > 0) {
      // the newest sample at least a nominal period back (else the oldest kept)
      std::size_t k = 0;
      for (; k + 1 < accel_n_; ++k)
        if (accel_now_s_ - accel_t_[(accel_head_ + kAccelRing - k) % kAccelRing] >=
            nominal_s * (1.0 - 1e-9))
          break;
      const std::size_t i = (accel_head_ + kAccelRing - k) % kAccelRing;
      const double span = accel_now_s_ - accel_t_[i];
      if (span > 0.0) {
        const double wdw = omega * (omega - accel_w_[i]) / span;
        if (std::isfinite(wdw)) wdw_ = wdw;
        accel = inertia_ * wdw;
      }
    }
    accel_head_ = (accel_head_ + 1) % kAccelRing;
    accel_t_[accel_head_] = accel_now_s_;
    accel_w_[accel_head_] = omega;
    if (accel_n_ < kAccelRing) ++accel_n_;
    if (std::isfinite(accel)) accel_W_ = accel;
  }
  const core::FirstOrderLag lag(dt, p_.power_lag_s);  // the meter's
  accel_lagged_W_ = lag.step_increment(accel_lagged_W_, accel_W_);
  wdw_lagged_ = lag.step_increment(wdw_lagged_, wdw_);
}

}  // namespace lathectl::control
