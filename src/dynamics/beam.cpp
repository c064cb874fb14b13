#include "lathectl/dynamics/beam.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::dynamics {

namespace {
void check(const BeamPart& p, double x) {
  if (!(p.length_m > 0.0) || !(p.diameter_m > 0.0) || !(p.youngs_modulus_Pa > 0.0) ||
      !(p.density_kg_per_m3 > 0.0) || !(p.damping_ratio > 0.0))
    throw std::invalid_argument("beam: length, diameter, E, ρ and ζ must be > 0");
  if (!(x > 0.0 && x < p.length_m))
    throw std::invalid_argument("beam: the cutting position must lie between the centres");
}
}  // namespace

BeamModeAt beam_mode_at(const BeamPart& p, double x, int j) noexcept {
  const double pi = std::numbers::pi;
  const double area = pi * p.diameter_m * p.diameter_m / 4.0;
  const double inertia = pi * std::pow(p.diameter_m, 4) / 64.0;
  const double L = p.length_m;
  const double modal_mass = p.density_kg_per_m3 * area * L / 2.0;
  const double w = std::pow(j * pi / L, 2) *
                   std::sqrt(p.youngs_modulus_Pa * inertia / (p.density_kg_per_m3 * area));
  const double phi = std::sin(j * pi * x / L);
  const double phi2 = std::max(phi * phi, 1e-12);
  return {{modal_mass * w * w / phi2, p.damping_ratio, w / (2.0 * pi), p.angle_rad},
          modal_mass / phi2,
          phi};
}

std::vector<Mode> beam_modes_at(const BeamPart& p, double x, int n_modes) {
  check(p, x);
  std::vector<Mode> out;
  for (int j = 1; j <= n_modes; ++j) {
    const BeamModeAt m = beam_mode_at(p, x, j);
    if (std::abs(m.shape) < 1e-6) continue;  // a node at the tool: this mode is not seen
    out.push_back(m.mode);
  }
  return out;
}

double beam_static_stiffness(const BeamPart& p, double x) {
  check(p, x);
  const double inertia = std::numbers::pi * std::pow(p.diameter_m, 4) / 64.0;
  const double L = p.length_m;
  return 3.0 * p.youngs_modulus_Pa * inertia * L / (x * x * (L - x) * (L - x));
}

}  // namespace lathectl::dynamics
