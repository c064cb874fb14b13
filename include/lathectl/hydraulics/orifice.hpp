#pragma once
// Sharp-edged annular slot in a spool valve (seed 000, formula (1) without the pulse factor):
//   q = μ · π · d · h · sqrt(2 Δp / ρ)        [m³/s]
// (the seed writes 2gΔp/γ with γ = ρg, the same thing). μ ≈ 0.65 for a sharp slot.

#include <cmath>

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
// (flush) or, in a spool valve, the edge sweep of each closing stroke removes it. Model:
//   dδ/dt = (δ_max − δ)/τ   while the gap is open and below the critical gap,
//   δ ← 0                   on a flush (opening ≥ critical gap, or a closing stroke),
//   effective opening = max(h − 2δ, 0)  (a layer on both walls).
// Layer thickness of a few µm and times of minutes, after Bashta, "Hydraulic drives of machine
// tools" (obliteration of throttle gaps); the numbers are scenario parameters, not constants.
struct ObliterationParams {
  double layer_max_m = 0.0;        // δ_max per wall; 0 disables
  double time_constant_s = 600.0;  // τ
  double critical_gap_m = 20e-6;   // gaps at or above this do not silt
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
    if (h > 0.0) delta_ += (p_.layer_max_m - delta_) * (1.0 - std::exp(-dt / p_.time_constant_s));
    return std::max(h - 2.0 * delta_, 0.0);
  }
  void flush() noexcept { delta_ = 0.0; }
  [[nodiscard]] double thickness_m() const noexcept { return delta_; }

 private:
  ObliterationParams p_{};
  double delta_ = 0.0;
};

}  // namespace lathectl::hydraulics
