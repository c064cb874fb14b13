#pragma once
// Vibro-contact transducer (ВКП) of seed 003, its equations (5)-(14) as a full electromechanical
// model:
//
//   electromagnet 2:  L·di/dt + r·i = V·sin ωt        (7), flux Φ = L·i/W
//                     F_m = a_f·Φ²                     (5): DC + a 2ω component
//   probe 1:          M·z'' + h·z' + k·z = F_m − F_c   (8), z from the probe's rest position
//   contact:          the part surface at z_s = z_eq + A0 − x (x: the controlled part of the
//                     size, so x = 0 grazes the free oscillation's crest and x = A0 stops it);
//                     F_c = max(0, k_c·p + c_c·ṗ) for penetration p = z − z_s > 0 (one-sided)
//   generator 3-4:    emf = K_g·ż (moving permanent-magnet flux through the coil, (10)-(11)),
//                     T_g·u' + u = emf                  (12)
//   rectifier 13:     g = |u|                           (13)
//   filter 14:        T_f·S' + S = g                     (14)
// The free amplitude of the 2ω component, A0 = (a_f·Φ_m²/2)/|k − M(2ω)² + j·h·2ω| with
// Φ_m = L·V/(W·sqrt(r² + ω²L²)), is the largest allowance it can measure.
//
// Integration: semi-implicit Euler for the probe (velocity first, contact force implicit in its
// stiffness so a stiff contact stays stable), exact first-order updates for the coil current
// lag (with the input held over the step), the generator and the filter. The step must resolve
// the contact: dt·sqrt(k_c/M) ≲ 0.5 (checked at configure).

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
  };
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
  struct Level {
    double mean_V = 0.0;
    double ripple_V = 0.0;
  };
  static Level settled_signal(const Params& p, double dt_s, double x_m, double settle_s,
                              double average_s);
  // Starts in the free steady oscillation (no contact) so no start-up transient is simulated.
  void reset() noexcept;
  // One step with the controlled part of the size x [m] (x ≤ 0: no contact). Returns S [V].
  double step(double x_m) noexcept;

  [[nodiscard]] double free_amplitude_m() const noexcept { return a0_; }
  [[nodiscard]] double static_offset_m() const noexcept { return z_eq_; }
  [[nodiscard]] double filtered_V() const noexcept { return s_; }
  [[nodiscard]] double probe_position_m() const noexcept { return z_; }
  [[nodiscard]] double time_s() const noexcept { return t_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // The seed's amplitude → signal gain: mean of |u| per metre of 2ω amplitude,
  // K = (2/π)·K_g·2ω/sqrt(1 + (2ω·T_g)²).
  [[nodiscard]] double signal_gain_V_per_m() const noexcept { return gain_; }

 private:
  Params p_{};
  double dt_ = 2e-5;
  double t_ = 0.0;
  double i_ = 0.0, z_ = 0.0, v_ = 0.0, u_ = 0.0, s_ = 0.0;
  double a0_ = 0.0, z_eq_ = 0.0, gain_ = 0.0;
  double coil_decay_ = 0.0, gen_decay_ = 0.0, filt_decay_ = 0.0;
  double omega_ = 0.0;
};

}  // namespace lathectl::sensors
