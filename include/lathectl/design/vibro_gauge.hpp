#pragma once
// Linearised vibro-contact gauging, seed 003 (20)-(25), SI units:
//   free 2ω amplitude      A0 = (a_f·Φ_m²/2)/|k − M(2ω)² + j·h·2ω|, Φ_m = L·V/(W·sqrt(r² + ω²L²))
//   signal gain            K  = (2/π)·K_g·2ω / sqrt(1 + (2ω·T_g)²)           [V per m]
//   mean filtered signal   T_f·S' + S = K·(B0/q1 − x),  B0/q1 = A0 in the seed's first
//                          approximation (the 2ω amplitude is A0 − x)         (20)
//   with x = m_x − a·t, after the lag: m_S(t) = K·(A0 − m_x + a·(t − T_f))   (21)
//   end of cut when m_x − a·t_k = x_k                                        (22)
//   threshold (relay trips at S = S_th, command t_r later):
//                          S_th = K·(A0 − x_k − a·(T_f + t_r))               (23)
//   noise through the filter, ξ with R(τ) = D·e^{−β|τ|}:
//                          D_y = D·K² / (1 + β·T_f)                          (25)
//   size scatter (a threshold crossing converts signal noise to size by 1/K): σ_x =
//   sqrt(D/(1+βT_f)) largest allowance it can measure: A0.
// The full model (sensors/vibro_contact_gauge.hpp) shows where these hold.

namespace lathectl::design {

struct GaugeInput {
  // transducer
  double supply_V = 24.0, supply_Hz = 50.0, coil_turns = 1000.0, coil_resistance_ohm = 50.0,
         coil_inductance_H = 0.5, force_coefficient_N_per_Wb2 = 2e8, probe_mass_kg = 0.02,
         probe_damping_N_s_per_m = 1.4, probe_stiffness_N_per_m = 9500.0,
         generator_V_per_m_per_s = 50.0, generator_time_constant_s = 2e-4,
         filter_time_constant_s = 0.1, relay_response_s = 0.02;
  // process
  double allowance_m = 200e-6;       // m_x
  double removal_m_per_s = 20e-6;    // a
  double target_m = 50e-6;           // x_k
  double noise_variance_m2 = 4e-12;  // D
  double noise_beta_per_s = 5.0;     // β
};

struct GaugeResult {
  double free_amplitude_m = 0.0;     // A0 = the largest measurable allowance
  double signal_gain_V_per_m = 0.0;  // K
  double intercept_m = 0.0;          // B0/q1 (= A0 here)
  double signal_at_target_V = 0.0;   // K·(A0 − x_k)
  double threshold_V = 0.0;          // (23)
  double end_time_s = 0.0;           // (22)
  double noise_variance_V2 = 0.0;    // D_y (25)
  double size_sigma_m = 0.0;         // σ_x
  double static_offset_m = 0.0;      // DC deflection of the probe
};

// Throws std::invalid_argument naming the bad input.
GaugeResult gauge(const GaugeInput& in);

}  // namespace lathectl::design
