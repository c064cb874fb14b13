#pragma once
// Vibro-contact transducer (ВКП) of seed 003, its equations (5)-(14) as a full electromechanical
// model:
//
//   electromagnet 2:  W·dΦ/dt + r·i = V·sin ωt         (7)
//                     Φ = (L·i/W)·δ/(δ − z)            (6) as read in docs/system-d-gauging.md:
//                       the flux of a magnetic circuit whose
//                       reluctance is its effective air gap δ − z (iron included); L is the
//                       inductance at rest. δ = 0 (magnet_gap_m) keeps the seed's linear coil
//                       Φ = L·i/W. Consistent with (5): a_f = 1/(2μ₀S) and L = μ₀S·W²/δ give
//                       δ = W²/(2·a_f·L) (4.74 mm for d_gauging).
//                     F_m = a_f·Φ²                     (5): DC + a 2ω component
//   permanent magnet 3 (9)-(11): F = F_m + F_M (9), F_M = a₂·Φ_M² (10), Φ_M = b₁/(b₂ − z) (11):
//                       F_M = F_M0·(b₂/(b₂ − z))², F_M0 the
//                       pull at rest (pm_force_N), b₂ the magnet's gap (pm_gap_m; 0: none).
//   probe 1:          M·z'' + h·z' + k·z = F − F_c     (8), z from the spring's free position,
//                       positive towards the part and the magnets
//   contact:          the part surface at z_s = z_crest − x (x: the controlled part of the
//                     size, so x = 0 grazes the free oscillation's crest and x = A0 stops it);
//                     F_c = max(0, k_c·p + c_c·ṗ) for penetration p = z − z_s > 0 (one-sided)
//   generator 3-4:    emf = W_g·dΦ_M/dt = K_g·(b₂/(b₂ − z))²·ż (10)-(11), K_g = W_g·b₁/b₂² its
//                       gain at rest (linear, emf = K_g·ż, without a magnet gap),
//                     T_g·u' + u = emf                  (12)
//   rectifier 13:     g = |u|                           (13)
//   filter 14:        first order   T_f·S' + S = g      (14), the seed's
//                     second order  two lags T_f/2 in cascade: the same ramp lag T_f, the 2ω
//                                   ripple down by a further ~ωT_f/2
//                     synchronous   the mean of g over the last T_w = 2n supply periods
//                                   (T_w the even number of periods nearest 2·T_f): the ramp
//                                   lag T_w/2, and every harmonic of ω/2 (the 2ω ripple, its
//                                   period-doubled and period-quadrupled subharmonics) nulled
// The free amplitude of the 2ω component in the seed's linear model, A0 = (a_f·Φ_m²/2)/|k −
// M(2ω)² + j·h·2ω| with Φ_m = L·V/(W·sqrt(r² + ω²L²)), is the largest allowance it can measure;
// with (6) or (9)-(11) the free oscillation is simulated at configure() instead and A0 is half its
// peak-to-peak.
//
// Integration: semi-implicit Euler for the probe (velocity first, contact force implicit in its
// stiffness so a stiff contact stays stable), exact first-order updates for the flux (with the
// input and the gap held over the step), the generator and the filter(s). The step must resolve
// the contact: dt·sqrt(k_c/M) ≲ 0.5 (checked at configure).

#include <cstddef>

#include "lathectl/core/first_order_lag.hpp"
#include "lathectl/sensors/gauge_filter.hpp"

namespace lathectl::sensors {

class VibroContactGauge {
 public:
  struct Params {
    double supply_V = 24.0;                    // V (amplitude)
    double supply_Hz = 50.0;                   // ω/2π; the probe is driven at 2ω
    double coil_turns = 1000.0;                // W
    double coil_resistance_ohm = 50.0;         // r
    double coil_inductance_H = 0.5;            // L
    double force_coefficient_N_per_Wb2 = 2e8;  // a_f
    double probe_mass_kg = 0.02;               // M
    double probe_damping_N_s_per_m = 1.4;      // h
    double probe_stiffness_N_per_m = 9500;     // k
    double contact_stiffness_N_per_m = 1e6;    // k_c
    double contact_damping_N_s_per_m = 5.0;    // c_c
    double generator_V_per_m_per_s = 50.0;     // K_g
    double generator_time_constant_s = 2e-4;   // T_g
    double filter_time_constant_s = 0.1;       // T_f
    double magnet_gap_m = 0.0;                 // δ of (6); 0: flux independent of the gap
    double pm_force_N = 0.0;                   // F_M0, the permanent magnet's pull at rest
    double pm_gap_m = 0.0;                     // b₂ of (11); 0: linear generator, no F_M(z)
    using Filter = sensors::GaugeFilterKind;
    Filter filter = Filter::FirstOrder;
  };
  // The synchronous filter's window: the even number of supply periods nearest 2·T_f (≥ 2).
  static double synchronous_window_s(const Params& p) noexcept;
  // The filter's ramp lag (the delay of a ramp through it): T_f, T_f, T_w/2.
  static double filter_lag_s(const Params& p) noexcept;
  // The variance of OU noise (R = D·e^{−β|τ|}) through the filter, per unit D:
  //   first order 1/(1 + βT_f) (seed (25)); second order (βτ + 2)/(2(1 + βτ)²), τ = T_f/2;
  //   synchronous 2(x − 1 + e^{−x})/x², x = βT_w.
  static double filter_noise_factor(const Params& p, double beta_per_s) noexcept;
  [[nodiscard]] bool nonlinear() const noexcept {
    return p_.magnet_gap_m > 0.0 || p_.pm_gap_m > 0.0 || p_.pm_force_N != 0.0;
  }
  void configure(const Params& p, double dt_s);  // throws std::invalid_argument
  // The closed forms alone, without a simulation step (for the design calculator).
  struct Steady {
    double free_amplitude_m;     // A0
    double static_offset_m;      // DC deflection F_dc/k
    double signal_gain_V_per_m;  // K
  };
  static Steady steady(const Params& p) noexcept;
  // The settled filtered signal at a fixed x (no removal, no noise): its mean over `average_s`
  // after `settle_s`, and its ripple (half its peak-to-peak there). Throws as configure().
  // spread_m: the spread of the probe position sampled once per 2ω period (its Poincaré
  // section) over the averaging window: ≈ 0 when the probe repeats every drive period (regular),
  // large when it period-doubles or wanders (a chaotic trip time: design/vibro_gauge.hpp).
  struct Level {
    double mean_V = 0.0;
    double ripple_V = 0.0;
    double spread_m = 0.0;
  };
  static Level settled_signal(const Params& p, double dt_s, double x_m, double settle_s,
                              double average_s);
  // Starts in the free steady oscillation (no contact) so no start-up transient is simulated.
  // Allocation-free (configure() sizes the synchronous filter's buffer).
  void reset() noexcept;
  // One step with the controlled part of the size x [m] (x ≤ 0: no contact). Returns S [V].
  double step(double x_m) noexcept;
  // One step of the transducer alone: the generator's signal u [V], for a machine side that
  // rectifies and filters it itself (control::GaugeMachine); filtered_V() is then not updated.
  double step_generator(double x_m) noexcept;
  // The filtered signal of the free probe (no contact), where reset() starts the filter.
  [[nodiscard]] double free_signal_V() const noexcept { return free_.s; }
  [[nodiscard]] double generator_V() const noexcept { return u_; }
  // The filter's parameters as the machine side's GaugeFilter takes them.
  [[nodiscard]] static sensors::GaugeFilter::Params filter_params(const Params& p) noexcept {
    return {p.filter, p.filter_time_constant_s, p.supply_Hz};
  }

  [[nodiscard]] double free_amplitude_m() const noexcept { return a0_; }
  [[nodiscard]] double static_offset_m() const noexcept { return z_eq_; }
  [[nodiscard]] double filtered_V() const noexcept { return filter_.value(); }
  [[nodiscard]] double probe_position_m() const noexcept { return z_; }
  [[nodiscard]] double time_s() const noexcept { return t_; }
  [[nodiscard]] double step_s() const noexcept { return dt_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // The seed's amplitude → signal gain: mean of |u| per metre of 2ω amplitude,
  // K = (2/π)·K_g·2ω/sqrt(1 + (2ω·T_g)²).
  [[nodiscard]] double signal_gain_V_per_m() const noexcept { return gain_; }

 private:
  struct State {
    double t0 = 0.0;  // supply phase offset [s] of the free steady state
    double phi = 0.0, z = 0.0, v = 0.0, u = 0.0, s = 0.0;
  };
  void linear_free_state() noexcept;
  Params p_{};
  double dt_ = 2e-5;
  double t_ = 0.0;
  double phi_ = 0.0, z_ = 0.0, v_ = 0.0, u_ = 0.0;
  double a0_ = 0.0, z_eq_ = 0.0, gain_ = 0.0;
  core::FirstOrderLag coil_lag_, gen_lag_;  // the flux's (free gap) and the generator's
  double omega_ = 0.0;
  State free_{};  // the free steady state reset() starts from
  sensors::GaugeFilter filter_;  // rectifier (13) and filter (14)
};

}  // namespace lathectl::sensors
