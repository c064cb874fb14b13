#pragma once
// Linear stability of one regenerative loop in its general form, for the set-ups of rig B:
//   1 + g·Φ(jω)·(1 − c·e^{−jωT}) = 0
// Φ the oriented FRF of the modes (dynamics/lobes.hpp), g the cutting gain dF/db [N/m], T the
// delay and c the coupling:
//   one tool, overlap μ:            T = τ = 60/n,  c = +μ   (the classic regenerative loop)
//   twin turrets in feed division:  T = τ/2,       c = −μ   (each tool cuts the surface the
//                                   opposite tool left half a turn earlier; the opposite side
//                                   flips the sign), g = g₁ + g₂
// The critical gain at a speed is the smallest g > 0 for which some ω satisfies the equation:
// Im[Φ(1 − c·e^{−jωT})] = 0 with Re < 0 gives g = −1/Re[...]. Found by scanning ω and refining
// each sign change of the imaginary part by bisection. Independent of the lobe construction in
// lobes.cpp (which inverts the phase condition for the speed): a cross-check of both and of the
// time-domain rig.

#include <vector>

#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::dynamics {

struct CriticalGain {
  double gain_N_per_m = 0.0;  // +inf when no crossing was found in the band
  double chatter_Hz = 0.0;
};

// Scans f ∈ [f_lo, f_hi] Hz with `points` samples. Throws std::invalid_argument on bad input.
CriticalGain critical_gain(const std::vector<Mode>& modes, double delay_s, double coupling,
                           double f_lo_Hz, double f_hi_Hz, int points = 20000);

}  // namespace lathectl::dynamics
