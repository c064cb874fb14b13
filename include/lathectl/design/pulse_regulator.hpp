#pragma once
// Design formulas of seed 000 (SI units throughout):
//   (1) Q  = μ·π·d·h·sqrt(2Δp/ρ)·Δt/T            mean regulator flow
//   (2) Ka = μ·π·d·sqrt(2Δp/ρ)·Δt/T               AIM gain, Q = Ka·h
//   (3) S  = Q/F − K_leak·Py/F²                   slide velocity with internal leakage
//   (4) Δh = K_leak·ΔPy/(Ka·F)                    AIM slot correction for a force change
//   (6) Kf = μ·π·d·h·sqrt(2Δp/ρ)·Δt               FIM gain, Q = Kf·f
//       Δf = K_leak·ΔPy/(Kf·F)                    FIM frequency correction (the (4) analogue)
//       duty = Δt/T = Δt·f
// The seed writes 2gΔp/γ (γ specific weight): with γ = ρg it is 2Δp/ρ.

namespace lathectl::design {

struct PulseRegulatorInput {
  double spool_diameter_m = 0.0;        // d
  double slot_m = 0.0;                  // h
  double pressure_drop_Pa = 0.0;        // Δp
  double density_kg_per_m3 = 870.0;     // ρ
  double discharge_coefficient = 0.65;  // μ
  double pulse_width_s = 0.0;           // Δt
  double period_s = 0.0;                // T = 1/f
  double piston_area_m2 = 0.0;          // F
  double leak_m3_per_s_Pa = 0.0;        // K_leak
  double force_N = 0.0;                 // Py
  double force_change_N = 0.0;          // ΔPy
};

struct PulseRegulatorResult {
  double flow_m3_per_s = 0.0;         // Q (1)
  double ka_m2_per_s = 0.0;           // Ka (2) [m³/s per m]
  double kf_m3 = 0.0;                 // Kf (6) [m³/s per Hz]
  double feed_m_per_s = 0.0;          // S (3)
  double feed_no_leak_m_per_s = 0.0;  // Q/F
  double slot_change_m = 0.0;         // Δh (4)
  double frequency_change_Hz = 0.0;   // Δf
  double duty = 0.0;                  // Δt/T
  double frequency_Hz = 0.0;          // f
  double leak_m3_per_s = 0.0;         // K_leak·Py/F
};

// Throws std::invalid_argument naming the bad input.
PulseRegulatorResult pulse_regulator(const PulseRegulatorInput& in);

}  // namespace lathectl::design
