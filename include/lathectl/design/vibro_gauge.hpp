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
// The full model (sensors/vibro_contact_gauge.hpp) shows where these hold, and bounds them: the
// relay trips on the signal rising through S_th, so S_th must lie above the signal at the start of
// the cut and below the free (no contact) signal, each with a margin for noise and ripple. Near
// A0 the probe bounces off the part and the signal keeps a floor (≈ 1.1 V for d_gauging, where
// (20) says 0): a threshold below it is never crossed and the cut never ends.

#include "lathectl/sensors/vibro_contact_gauge.hpp"

namespace lathectl::design {

// The signal range the full model reaches (simulated on a grid of x, not a constant):
//   S(x) falls from free_V (x = 0, the crest grazes the part) while the probe's amplitude is
//   clipped, until floor_start_m (found walking back from the allowance to the first fall larger
//   than the ripple); beyond it the probe bounces and S stays on a floor (≈ 1.1 V for
//   d_gauging, not 0 as (20) says), even rising again. floor_V = the largest S on [floor_start_m,
//   allowance] (the relay, armed below its threshold, must see the signal there under it);
//   margin = the largest ripple there + 4·σ_y (σ_y of (25), the noise through the filter);
//   a usable threshold lies in [low_V, high_V] = [floor_V + margin, max S − margin] (max S is
//   free_V unless a light contact raises the signal, as with the resonance below 2ω).
struct SignalRange {
  double start_V = 0.0;        // S at x = allowance
  double floor_V = 0.0;        // the floor's highest signal
  double floor_start_m = 0.0;  // where S(x) stops falling
  double free_V = 0.0, ripple_V = 0.0, noise_sigma_V = 0.0;
  double low_V = 0.0, high_V = 0.0;
  [[nodiscard]] bool contains(double s) const { return s >= low_V && s <= high_V; }
};
// Step for simulating the full model: resolves the contact and the supply (configure()'s rules).
double full_model_step(const sensors::VibroContactGauge::Params& p);
// Settling time before a settled signal is read: 8·T_f, at least 0.8 s.
double full_model_settle(const sensors::VibroContactGauge::Params& p);
SignalRange signal_range(const sensors::VibroContactGauge::Params& p, double dt_s,
                         double allowance_m, double noise_sigma_V);
// The size x in [x_lo, x_hi] at which the full model's settled mean signal equals level_V
// (bisection on the falling S(x), x_hi ≤ floor_start_m; x_lo or x_hi when the level lies outside
// their signals).
double size_at_signal(const sensors::VibroContactGauge::Params& p, double dt_s, double level_V,
                      double x_lo, double x_hi);

struct GaugeInput {
  // transducer
  double supply_V = 24.0, supply_Hz = 50.0, coil_turns = 1000.0, coil_resistance_ohm = 50.0,
         coil_inductance_H = 0.5, force_coefficient_N_per_Wb2 = 2e8, probe_mass_kg = 0.02,
         probe_damping_N_s_per_m = 1.4, probe_stiffness_N_per_m = 9500.0,
         contact_stiffness_N_per_m = 1e6, contact_damping_N_s_per_m = 5.0,
         generator_V_per_m_per_s = 50.0, generator_time_constant_s = 2e-4,
         filter_time_constant_s = 0.1, relay_response_s = 0.02;
  // (6) and (9)-(11) (0: the seed's linear coil and generator), and the filter's kind
  double magnet_gap_m = 0.0, pm_force_N = 0.0, pm_gap_m = 0.0;
  sensors::VibroContactGauge::Params::Filter filter =
      sensors::VibroContactGauge::Params::Filter::FirstOrder;
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
  SignalRange range;                 // what the full model's signal reaches, with its margin
  // The largest target whose (23) threshold is still in range: S_full(x_k + a(T_f + t_r)) =
  // range.low_V on the falling branch. Where the safe range of targets ends.
  double largest_target_m = 0.0;
  // The design rule: the probe's Poincaré spread at the trip point x_k + a·(lag + t_r), and
  // whether it is regular (spread ≤ kRegularSpread·A0).
  double trip_spread_m = 0.0;
  bool regular = true;
};

// A straight line S = K·(B − x) for (23): the seed's (K, A0), or the full model's local line.
struct GaugeLine {
  double gain_V_per_m = 0.0;  // K
  double intercept_m = 0.0;   // B (B0/q1)
  double spread_m = 0.0;      // calibrated: the probe's largest Poincaré spread at the points
};
// The design rule for a regular impact: the probe must repeat its impact every drive period at
// the trip point — its Poincaré spread at most this fraction of A0. Found by simulation (not a
// closed form): with the seed's contact (k_c = 10⁶ N/m, c_c = 5 N·s/m: restitution e ≈ 0.95) and
// the resonance above 2ω (110 Hz against 100 Hz) the probe period-doubles (spread 0.10-0.16·A0) and
// the trip time is chaotic (a 1e-12 change of k moves the finished size by 0.2-0.4 µm); a damped
// contact (c_c ≥ 100 N·s/m: ζ_c = c_c/(2·sqrt(k_c·M)) ≥ 0.35, e ≤ 0.3), a softer one (k_c = 10⁵
// N/m) or a resonance at or below 2ω (f_n ≤ 2f: 90-100 Hz) keeps it regular (spread ≤ 0.02·A0).
constexpr double kRegularSpread = 0.03;
// (23): S_th = K·(B − x_k − a·lag_s), lag_s = T_f + t_r for the first-order filter.
double threshold_23(const GaugeLine& line, double target_m, double removal_m_per_s, double lag_s);
// What (22), (23) and (25) give for a line (K, B) and the process, filter and relay of `in`
// (its transducer fields unused but supply_Hz, which the synchronous filter's window needs):
// gauge() for the transducer's line, `design gauge --calibration` for a measured one.
struct ProcessNumbers {
  double signal_at_target_V = 0.0;  // K·(B − x_k)
  double threshold_V = 0.0;         // (23)
  double end_time_s = 0.0;          // (22)
  double noise_variance_V2 = 0.0;   // D_y (25), for the filter of `in`
  double size_sigma_m = 0.0;        // σ_x
  double lag_m = 0.0;               // a·(filter lag + t_r): the trip is this far above x_k
};
ProcessNumbers process_numbers(const GaugeLine& line, const GaugeInput& in);

// The full model's local line: least squares through its settled mean signal at x_trip + 10 µm·i,
// i = −2…2 (the calibration a shop makes with setting masters around the trip point).
GaugeLine calibrated_line(const sensors::VibroContactGauge::Params& p, double dt_s,
                          double x_trip_m);

// Throws std::invalid_argument naming the bad input. Simulates the full model (a few ms).
GaugeResult gauge(const GaugeInput& in);

}  // namespace lathectl::design
