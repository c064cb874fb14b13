#pragma once
// A measured frequency response function (a tap test's receptance, m/N) in the chatter model:
// its value between the measured frequencies, the smoothing a noisy measurement needs before the
// frequency-domain lobes take a minimum of it, and a modal fit for the methods that need modes
// (semi-discretization, the time-domain rigs, `optimize`'s chatter margin).
//
// Modal fit (peak picking refined by least squares; Ewins, "Modal Testing", 2nd ed., 2000,
// ch. 4.3–4.4): a receptance of M modes in one direction is
//   Ĥ(f) = Σ 1/(k_m·(1 − r_m² + 2j·ζ_m·r_m)),  r_m = f/f_m.
// Modes are added one at a time: the largest peak of |H − Ĥ| gives f_m; its half-power
// bandwidth Δf (|H| ≥ peak/√2) gives ζ_m = Δf/(2·f_m); the peak height |H|max = 1/(2k·ζ) gives
// k_m. After each addition every parameter (ln f_m, ln ζ_m, ln k_m) is refined together by
// Levenberg–Marquardt on the complex residual. Modes are added while the relative residual
//   ρ = √(Σ|H − Ĥ|² / Σ|H|²)
// falls by more than a third with the new mode (noise of a few per cent leaves ρ at about its
// own level, which another mode cannot lower by that much) and every mode stays inside the
// measured band with ζ ≤ 0.5, up to max_modes.

#include <complex>
#include <cstddef>
#include <vector>

#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::dynamics {

// Frf (lobes.hpp): throws std::invalid_argument unless it has ≥ 2 samples, frequencies strictly
// ascending and > 0, and finite values.
void check_frf(const Frf& frf);

// Linear interpolation of the real and imaginary parts; 0 outside the measured band.
std::complex<double> frf_at(const Frf& frf, double f_Hz) noexcept;

// The FRF of modes (angle θ weighs each by cos²θ, as the lobes' oriented FRF) at f_Hz.
std::complex<double> modal_frf(const std::vector<Mode>& modes, double f_Hz) noexcept;

// Local polynomial regression (degree `order`) of the real and imaginary parts over
// ±half_window_Hz around each sample (Savitzky–Golay on a possibly uneven grid): noise averaged
// over the window, a peak much wider than the window kept. half_window_Hz ≤ 0: unchanged.
Frf smooth_frf(const Frf& frf, double half_window_Hz, int order = 2);

struct FrfFit {
  std::vector<Mode> modes;  // angle 0: the fit is of the FRF as given (already oriented)
  double residual = 0.0;    // ρ above
  int iterations = 0;
};
// Throws std::invalid_argument on an invalid FRF or one with no peak.
FrfFit fit_modes(const Frf& frf, int max_modes = 6);

// The smoothing a measured FRF gets before the frequency-domain lobes take a minimum of it: a
// quartic over ±¾ of the sharpest fitted peak's half-power half-width, min over modes of
// 0.75·ζ·f. Chosen on synthetic tap tests (tests/dynamics/frf_test.cpp) among quadratic,
// quartic and sextic fits over ¼ to 1½ half-widths: unsmoothed, 1–3 % noise lowers the limit
// by 3.5–10 % (the minimum of noisy samples); at ¼ half-width the quadratic still by 0.6–1.8 %;
// wider windows flatten the peak.
inline constexpr int kSmoothingOrder = 4;
double smoothing_half_window_Hz(const FrfFit& fit) noexcept;

// Σ of the FRFs (each on its own grid) on the union of their bands' overlap: the grid of the
// first, restricted to where every other is measured.
Frf sum_frfs(const std::vector<Frf>& frfs);

}  // namespace lathectl::dynamics
