#pragma once
// A slender part between centres (system B): an Euler–Bernoulli beam, pinned at both centres,
// seen at the cutting position. Mode j: shape φ_j(x) = sin(jπx/L), ω_j = (jπ/L)²·sqrt(EI/(ρA)),
// modal mass ρAL/2 for the unit-amplitude shape. Seen at the tool (x_c), mode j acts as a
// single-DOF mode of stiffness k_j/φ_j(x_c)² and mass m_j/φ_j(x_c)² (the same frequency): stiff
// near the centres, softest mid-span. Optional centre compliance adds in series as a rigid-body
// mode (headstock and tailstock springs; not modelled here).

#include <vector>

#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::dynamics {

struct BeamPart {
  double length_m = 0.5;
  double diameter_m = 0.03;
  double youngs_modulus_Pa = 2.1e11;
  double density_kg_per_m3 = 7850.0;
  double damping_ratio = 0.02;  // each mode
  double angle_rad = 0.0;       // mode direction to the chip thickness
};

// Mode j (1-based) seen at x_c: its equivalent stiffness and mass there, and the shape value
// φ_j(x_c) (for rescaling modal coordinates as the tool moves). No checks, no allocation: for
// rigs that recompute it as the cutting position moves (validate the part with beam_modes_at).
struct BeamModeAt {
  Mode mode;
  double mass_kg = 0.0;
  double shape = 0.0;
};
BeamModeAt beam_mode_at(const BeamPart& part, double x_c_m, int j) noexcept;

// The first `n_modes` modes as seen at the cutting position x_c (0 < x_c < L).
std::vector<Mode> beam_modes_at(const BeamPart& part, double x_c_m, int n_modes = 3);
// Static stiffness at x_c (point load on a pinned-pinned beam): 3EIL/(x²(L−x)²).
double beam_static_stiffness(const BeamPart& part, double x_c_m);

}  // namespace lathectl::dynamics
