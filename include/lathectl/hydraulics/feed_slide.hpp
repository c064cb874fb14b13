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
// Cavitation (the oil cannot carry tension). When the slide runs ahead of the inflow — its own
// momentum after a pulse, with little damping and no damper — the chamber pressure falls to the
// cavitation pressure p_cav (taken as 0 gauge, the level the rest of the model treats as tank)
// and the oil column separates: the motion opens a void (vapour and released air) of volume
// V_void ≥ 0 instead of pulling the pressure below p_cav:
//   V_void > 0:  p_c = p_cav = 0,   dV_void/dt = F·v − q_d       (no leakage at p_c = 0)
//   V_void = 0:  the chamber equation above, p_c ≥ 0
// A step that would take p_c below 0 turns the deficit into void, V_void = −p_c·V_c/B; net inflow
// must refill the void before the pressure rises again (the rest of the step's inflow
// compresses the oil: p_c = B·(excess)/V_c). So the oil volume is conserved: with the stored
// volume W = ∫V_c·dp_c/B of the compressed oil and C_d·p_d in the damper,
//   ∫(q_in − q_leak) dt = F·Δx + ΔW + C_d·Δp_d − ΔV_void          (exact, step by step)
// The earlier model clamped the pressure at 0 and forgot the void: the oil the slide
// "sucked" past the inflow appeared from nothing, and a light, undamped slide (no damper,
// b = 2000 N·s/m, system A) travelled 48.5 mm/min on (Q − q_leak)/F = 40.3 mm/min.
// The damper cannot deliver oil it does not hold: q_d ≤ q_in + C_d·p_d/dt (p_d ≥ 0).
//
// Integration: semi-implicit (symplectic) Euler — velocity first with the old pressure, then
// pressures with the new velocity — stable for ω_h·dt < 2, ω_h = F·sqrt(B/(V_c·m)). The rig
// checks the step against ω_h at configure. Stiction: if the velocity would cross zero and the
// driving force is below F_c, the slide sticks (v = 0).

#include <algorithm>
#include <cmath>

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
    double void_m3 = 0.0;  // V_void: cavitated (empty) volume in the chamber, p_cyl = 0 while > 0
  };
  // Oil delivered and leaked since configure() or reset_volume_ledger() [m³], and the storage
  // terms of the balance (see the header comment).
  struct VolumeLedger {
    double delivered_m3 = 0.0;  // ∫q_in dt
    double leaked_m3 = 0.0;     // ∫K_leak·p_c dt
    double compressed_m3 = 0.0; // W = ∫V_c·dp_c/B since the reset
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
  // Oil in the damper, C_d·p_d [m³].
  [[nodiscard]] double damper_volume() const noexcept {
    return p_.damper_capacitance_m3_per_Pa * s_.p_damper_Pa;
  }
  [[nodiscard]] const VolumeLedger& ledger() const noexcept { return ledger_; }
  void reset_volume_ledger() noexcept { ledger_ = {}; }

 private:
  Params p_{};
  State s_{};
  VolumeLedger ledger_{};
};

// In the header: every rig steps it every step (rig A: 600 000 times per simulated minute); out
// of line, the call and the reloads around it cost as much as its arithmetic
// (docs/code-layout.md, "Speed": the hand-written loops).
inline void FeedSlide::step(double dt, double q_in, double load_N) noexcept {
  const double F = p_.piston_area_m2;
  // Velocity (semi-implicit in viscous friction).
  const double drive = F * s_.p_cyl_Pa - load_N;
  const double fc = p_.coulomb_friction_N;
  const double m = p_.mass_kg;
  const double b = p_.viscous_friction_N_s_per_m;
  double v = s_.v_m_per_s;
  if (v == 0.0 && std::abs(drive) <= fc) {
    v = 0.0;  // stuck: static friction balances the drive
  } else {
    const double sgn = v != 0.0 ? (v > 0.0 ? 1.0 : -1.0) : (drive > 0.0 ? 1.0 : -1.0);
    const double v_new = (m * v + dt * (drive - fc * sgn)) / (m + dt * b);
    // Crossing zero: stop there; it moves on next step only if the drive beats stiction.
    v = (v != 0.0 && v_new * v < 0.0) ? 0.0 : v_new;
  }
  s_.v_m_per_s = v;
  s_.x_m += v * dt;
  // Pressures with the new velocity.
  double q_d = q_in;
  if (p_.damper_capacitance_m3_per_Pa > 0.0) {
    // The damper delivers at most what it holds (p_d ≥ 0).
    q_d = std::min((s_.p_damper_Pa - s_.p_cyl_Pa) / p_.damper_resistance_Pa_s_per_m3,
                   q_in + p_.damper_capacitance_m3_per_Pa * s_.p_damper_Pa / dt);
    s_.p_damper_Pa += dt * (q_in - q_d) / p_.damper_capacitance_m3_per_Pa;
    s_.p_damper_Pa = std::max(s_.p_damper_Pa, 0.0);
  }
  const double vol = p_.dead_volume_m3 + F * std::max(s_.x_m, 0.0);
  const double swept = F * v * dt;
  const double leak = p_.leak_m3_per_s_Pa * s_.p_cyl_Pa;  // 0 while cavitated
  ledger_.delivered_m3 += q_in * dt;
  ledger_.leaked_m3 += leak * dt;
  const double p_old = s_.p_cyl_Pa;
  if (s_.void_m3 > 0.0) {
    // Cavitated: the chamber sits at p_cav = 0; net inflow refills the void first.
    s_.void_m3 -= q_d * dt - swept;
    if (s_.void_m3 < 0.0) {  // refilled within the step: the rest compresses the oil
      s_.p_cyl_Pa = -s_.void_m3 * p_.bulk_modulus_Pa / vol;
      s_.void_m3 = 0.0;
    }
  } else {
    s_.p_cyl_Pa += dt * p_.bulk_modulus_Pa / vol * (q_d - F * v - leak);
    if (s_.p_cyl_Pa < 0.0) {  // no tension in oil: the deficit opens a void (cavitation)
      s_.void_m3 = -s_.p_cyl_Pa * vol / p_.bulk_modulus_Pa;
      s_.p_cyl_Pa = 0.0;
    }
  }
  ledger_.compressed_m3 += (s_.p_cyl_Pa - p_old) * vol / p_.bulk_modulus_Pa;
}

}  // namespace lathectl::hydraulics
