#pragma once
// Stock and roughing passes for longitudinal turning (system E): what the tool meets along z.
//
//   blank diameter D_b(z): piecewise linear through the given points (a forged, stepped or
//   tapered blank), its axis offset from the spindle axis by e (eccentric blank)
//   pass k cuts z ∈ [z_start, z_end] to diameter D_k, moving toward +z
//   surface before pass k at z: D_prev(z) = smallest D_j of the earlier passes covering z,
//                                           else the blank D_b(z)
//   depth: t(k, z, φ) = max(0, (D_prev(z) − D_k)/2 + e·sin φ [blank surface only])
// The cut diameter (for torque and cutting speed) is the outer one, D_prev(z) (+2e·sin φ on
// the blank).

#include <vector>

#include "lathectl/cutting/disturbances.hpp"

namespace lathectl::cutting {

struct Pass {
  bool operator==(const Pass&) const = default;
  double z_start_mm = 0.0;
  double z_end_mm = 0.0;
  double diameter_mm = 0.0;
};

struct StockParams {
  bool operator==(const StockParams&) const = default;
  std::vector<ProfilePoint> blank_diameter_mm;  // at_mm → diameter, ascending; ≥ 1 point
  double eccentricity_mm = 0.0;                 // offset of the blank's axis
  std::vector<Pass> passes;                     // in machining order
};

class Stock {
 public:
  void configure(const StockParams& p);  // throws std::invalid_argument; ≥ 1 pass
  // The blank alone, its passes not needed (a program's path cuts it: the LinuxCNC plant, the
  // optimiser's prediction); the pass queries then see the blank. Throws std::invalid_argument.
  void configure_blank(const StockParams& p);
  [[nodiscard]] double blank_diameter_mm(double z_mm) const noexcept;
  // Surface diameter in front of pass k at z (before eccentricity).
  [[nodiscard]] double surface_diameter_mm(std::size_t pass, double z_mm) const noexcept;
  [[nodiscard]] bool blank_surface(std::size_t pass, double z_mm) const noexcept;
  [[nodiscard]] double depth_mm(std::size_t pass, double z_mm, double phi_rad) const noexcept;
  [[nodiscard]] const StockParams& params() const noexcept { return p_; }
  // Largest depth any pass meets, eccentricity included (for worst-case settings).
  [[nodiscard]] double max_depth_mm() const noexcept;
  // Volume to remove [cm³] (exact for the piecewise-linear blank, eccentricity averaged out).
  [[nodiscard]] double volume_to_remove_cm3() const noexcept;

 private:
  StockParams p_{};
};

}  // namespace lathectl::cutting
