#pragma once
// Geometry of a canonical move: its length and the point at a share u ∈ [0, 1] of it (arcs in
// the XZ plane, θ = atan2(x − xc, z − zc), counter-clockwise for rotation > 0).
#include <utility>

#include "lathectl/io/canon.hpp"

namespace lathectl::optimize {

// Signed sweep of an arc [rad] (|rotation| > 1: extra full turns).
double arc_sweep(const io::CanonMove& m) noexcept;
double move_length(const io::CanonMove& m) noexcept;
std::pair<double, double> point_at(const io::CanonMove& m, double u) noexcept;  // (x, z)
// The spindle speed [rpm] at radius x: G97's S, G96's 1000·V/(2π·x) capped at D; 0 when off.
double spindle_rpm(const io::CanonMove& m, double x_mm);

}  // namespace lathectl::optimize
