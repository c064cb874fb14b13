#pragma once
// A slender part between centres (system B): an Euler–Bernoulli beam, pinned at both centres,
// seen at the cutting position. Mode j: shape φ_j(x) = sin(jπx/L), ω_j = (jπ/L)²·sqrt(EI/(ρA)),
// modal mass ρAL/2 for the unit-amplitude shape. Seen at the tool (x_c), mode j acts as a
// single-DOF mode of stiffness k_j/φ_j(x_c)² and mass m_j/φ_j(x_c)² (the same frequency): stiff
// near the centres, softest mid-span. Optional centre compliance adds in series as a rigid-body
// mode (headstock and tailstock springs; not modelled here).

#include <cstddef>
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

// Set-ups beyond centres: how each end is held, and an optional steady rest. Solved by finite
// elements (Hermite cubic Euler–Bernoulli elements, consistent mass; Przemieniecki, "Theory of
// Matrix Structural Analysis", 1968, ch. 5 and 11): K_e = EI/l³·[12, 6l, −12, 6l; 6l, 4l², −6l,
// 2l²; ...], M_e = ρAl/420·[156, 22l, 54, −13l; ...], the generalized eigenproblem K·φ = ω²·M·φ
// with φᵀMφ = 1. Seen at x_c, mode j is a single mode of stiffness ω_j²/φ_j(x_c)² (unit modal
// mass), as beam_mode_at's. Checked against the closed forms ω = (βL)²·√(EI/(ρAL⁴)) of each
// boundary condition (tests/dynamics/beam_test.cpp).
//   chuck (clamped–free, a cantilever):   βL = 1.87510, 4.69409, 7.85476
//   chuck and tailstock (clamped–pinned): βL = 3.92660, 7.06858, 10.21018
//   between centres (pinned–pinned):      βL = π, 2π, 3π
// A steady rest holds the part's axis at its position (no lateral displacement, free rotation).
enum class BeamEnd { free, pinned, clamped };
struct BeamSupports {
  BeamEnd headstock = BeamEnd::pinned;  // x = 0
  BeamEnd tailstock = BeamEnd::pinned;  // x = L
  double steady_rest_m = 0.0;           // > 0: a steady rest at this position (≤ L)
};
struct BeamModel {
  BeamPart part;
  BeamSupports supports;
  std::vector<double> nodes_m;                  // element ends, ascending, 0..L
  std::vector<double> omega_rad_s;              // per mode, ascending
  std::vector<std::vector<double>> shapes;      // per mode: (w, θ) at each node, φᵀMφ = 1
};
// Throws std::invalid_argument on a bad part, a rest outside (0, L] or a free–free beam.
BeamModel beam_model(const BeamPart& part, const BeamSupports& supports, int n_modes,
                     int elements = 160);
// φ_j(x) (j 0-based), by the elements' cubic shape functions.
double beam_model_shape(const BeamModel& model, std::size_t j, double x_m);
// The modes as seen at x (modes with a node at x left out, as beam_modes_at does).
std::vector<Mode> beam_model_modes_at(const BeamModel& model, double x_m);
// Static stiffness at x: the force over the deflection under a point load there (K·u = f).
double beam_model_static_stiffness(const BeamModel& model, double x_m);

}  // namespace lathectl::dynamics
