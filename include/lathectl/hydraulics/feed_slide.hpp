#pragma once
// Hydraulic feed slide of seed 000: damper 6, power cylinder 3 with leakage, slide 2 with mass
// and friction, pushed against the cutting load.
//
//   damper (gas-loaded volume, capacitance C_d) fed by the regulator flow q_in, discharging
//   into the cylinder through a laminar resistance R_d:
//     q_d = (p_d − p_c) / R_d
//     C_d · dp_d/dt = q_in − q_d
//   cylinder chamber, oil bulk modulus B, volume V_c = V_0 + F·x:
//     (V_c / B) · dp_c/dt = q_d − F·v − K_leak·p_c          (internal leakage, laminar)
//   slide:
//     m · dv/dt = F·p_c − P_load − b·v − F_c·sgn(v)         (Coulomb with stiction)
// In steady motion this gives seed (3): S = Q/F − K_leak·P/F² (with P = P_load + friction).
//
// Integration: semi-implicit (symplectic) Euler — velocity first with the old pressure, then
// pressures with the new velocity — stable for ω_h·dt < 2, ω_h = F·sqrt(B/(V_c·m)). The rig
// checks the step against ω_h at configure. Stiction: if the velocity would cross zero and the
// driving force is below F_c, the slide sticks (v = 0).

namespace lathectl::hydraulics {

class FeedSlide {
 public:
  struct Params {
    double piston_area_m2 = 20e-4;               // F
    double dead_volume_m3 = 100e-6;              // V_0: chamber and line volume at x = 0
    double bulk_modulus_Pa = 1.4e9;              // B of the oil (1–1.7 GPa)
    double leak_m3_per_s_Pa = 0.0;               // K_leak: q_leak = K_leak·p_c
    double damper_capacitance_m3_per_Pa = 0.0;   // C_d; 0 = no damper (q_d = q_in)
    double damper_resistance_Pa_s_per_m3 = 0.0;  // R_d
    double mass_kg = 50.0;                       // slide and tool
    double coulomb_friction_N = 0.0;             // F_c
    double viscous_friction_N_s_per_m = 0.0;     // b
  };
  struct State {
    double p_damper_Pa = 0.0;
    double p_cyl_Pa = 0.0;
    double x_m = 0.0;
    double v_m_per_s = 0.0;
  };
  void configure(const Params& p);  // throws std::invalid_argument
  // Puts the slide in steady motion at velocity v under load: pressures balanced, no transient.
  void set_steady(double v_m_per_s, double load_N) noexcept;
  void step(double dt, double q_in_m3_per_s, double load_N) noexcept;
  // Moves the origin of x without touching pressures or velocity (after a warm-up).
  void set_position(double x_m) noexcept { s_.x_m = x_m; }
  [[nodiscard]] const State& state() const noexcept { return s_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // Hydraulic natural frequency ω_h [rad/s] at the current volume.
  [[nodiscard]] double hydraulic_omega() const noexcept;
  [[nodiscard]] double leak_flow() const noexcept { return p_.leak_m3_per_s_Pa * s_.p_cyl_Pa; }

 private:
  Params p_{};
  State s_{};
};

}  // namespace lathectl::hydraulics
