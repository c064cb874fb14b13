#pragma once
// Sharp-edged annular slot in a spool valve (seed 000, formula (1) without the pulse factor):
//   q = μ · π · d · h · sqrt(2 Δp / ρ)        [m³/s]
// (the seed writes 2gΔp/γ with γ = ρg, the same thing). μ ≈ 0.65 for a sharp slot.

#include <cmath>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::hydraulics {

struct SlotOrifice {
  double spool_diameter_m = 0.008;      // d
  double discharge_coefficient = 0.65;  // μ
  double pressure_drop_Pa = 0.5e6;      // Δp, held constant by the reducing valve
  double density_kg_per_m3 = 870.0;     // ρ (mineral oil)

  // Flow per metre of slot opening [m³/s per m]: μ·π·d·sqrt(2Δp/ρ).
  [[nodiscard]] double gain_per_m() const noexcept {
    return discharge_coefficient * 3.14159265358979323846 * spool_diameter_m *
           std::sqrt(2.0 * pressure_drop_Pa / density_kg_per_m3);
  }
};

// Obliteration (silting) of a small gap: polar molecules of the oil adsorb on the gap walls and
// build a layer that grows with time while the gap is held at a small opening; a full opening
// (flush) removes it, and in a spool valve each closing stroke sweeps off a share η of it. Model:
//   dδ/dt = (δ_max − δ)/τ   while oil flows through a gap below the critical gap (a pulsed
//                           slot: while it is open),
//   δ ← 0                   on a flush (opening ≥ critical gap),
//   δ ← (1 − η)·δ           on a closing stroke (η = removal_per_stroke),
//   effective opening = max(h − 2δ, 0)  (a layer on both walls).
// Basis and its limits: the time law (flow decaying over minutes at gaps of a few to
// some tens of µm, with a layer of the order of a µm per wall, restored by a full opening or by
// relative motion of the walls — why servo valves are dithered) is the textbook description of
// obliteration (Bashta, "Mashinostroitel'naya gidravlika", 1971, obliteration of throttle gaps;
// Blackburn, Reethof & Shearer, "Fluid Power Control", 1960, silting of valves); the numbers are
// scenario parameters, not constants. How much of the layer a closing stroke removes (η) is not
// in those sources: η = 1 (the default, and what the seed's "no obliteration" assumes) is an
// assumption, and a_obliteration's report sweeps it. A pulse's growth g = 1 − e^(−Δt_open/τ)
// balances the removal at δ* = δ_max·g/(η + (1 − η)·g) ≈ δ_max·(Δt_open/τ)/η (η ≫ g); with
// η = 0 the slot silts toward δ_max, only over its open time.
struct ObliterationParams {
  double layer_max_m = 0.0;         // δ_max per wall; 0 disables
  double time_constant_s = 600.0;   // τ
  double critical_gap_m = 20e-6;    // gaps at or above this do not silt
  double removal_per_stroke = 1.0;  // η: share of the layer a closing stroke sweeps off
};

class ObliterationLayer {
 public:
  void configure(const ObliterationParams& p) noexcept {
    p_ = p;
    delta_ = 0.0;
  }
  // Grows the layer over dt at opening h; returns the effective opening.
  double step(double dt, double h) noexcept {
    if (p_.layer_max_m <= 0.0) return h;
    if (h >= p_.critical_gap_m) {
      delta_ = 0.0;
      return h;
    }
    if (h > 0.0)
      delta_ = core::FirstOrderLag(dt, p_.time_constant_s).step_increment(delta_, p_.layer_max_m);
    return std::max(h - 2.0 * delta_, 0.0);
  }
  void flush() noexcept { delta_ = 0.0; }
  // A closing stroke of the spool: sweeps off the share η of the layer.
  void sweep() noexcept { delta_ *= 1.0 - p_.removal_per_stroke; }
  [[nodiscard]] double thickness_m() const noexcept { return delta_; }

 private:
  ObliterationParams p_{};
  double delta_ = 0.0;
};

}  // namespace lathectl::hydraulics
