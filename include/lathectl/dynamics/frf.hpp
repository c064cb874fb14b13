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

// Linear interpolation of the real and imaginary parts; 0 outside the measured band. With a
// baseline (Frf::baseline: fitted modes), the baseline's FRF at f_Hz plus the linear
// interpolation of the samples' residual H_i − Ĥ(f_i): exact at the samples as before, and
// between them the peak's curvature is the modes', only the small residual is a straight line.
std::complex<double> frf_at(const Frf& frf, double f_Hz) noexcept;

// The FRF of modes (angle θ weighs each by cos²θ, as the lobes' oriented FRF) at f_Hz.
std::complex<double> modal_frf(const std::vector<Mode>& modes, double f_Hz) noexcept;

// Local polynomial regression (degree `order`) of the real and imaginary parts over
// ±half_window_Hz around each sample (Savitzky–Golay on a possibly uneven grid): noise averaged
// over the window, a peak much wider than the window kept. half_window_Hz ≤ 0: unchanged.
// Windows of up to kSmoothingDirectSamples samples are summed sample by sample (the numbers
// every example's lobes were computed with); wider ones from sums kept as the window slides, in
// O(n) instead of O(n·window) (a 40 001-row FRF took 51 s), equal to rounding.
inline constexpr std::size_t kSmoothingDirectSamples = 512;
Frf smooth_frf(const Frf& frf, double half_window_Hz, int order = 2);

struct FrfFit {
  std::vector<Mode> modes;  // angle 0: the fit is of the FRF as given (already oriented)
  double residual = 0.0;    // ρ above
  int iterations = 0;
};
// Throws std::invalid_argument on an invalid FRF or one with no peak.
FrfFit fit_modes(const Frf& frf, int max_modes = 6);

// The measured FRF read against its fitted modes (Frf::baseline = fit.modes): at each sample the
// fit plus the residual H − Ĥ smoothed (smooth_frf, ±half_window_Hz, `order`). The noise is
// averaged out of the residual alone, so the window does not flatten the peak, whose shape —
// between samples too (frf_at) — is the fit's.
Frf smooth_against_fit(const Frf& frf, const FrfFit& fit, double half_window_Hz, int order);

// The smoothing a measured FRF's residual from its fit gets before the frequency-domain lobes
// read it (smooth_against_fit): a quartic over ±3·ζ·f of the sharpest fitted peak (min over
// modes). Chosen on synthetic tap tests (tests/dynamics/frf_test.cpp; 50 noise draws at 1–3 %
// and 0.05–0.5 Hz spacing) among ±¾, ±1½ and ±3 ζf: the absolute limit's worst error over the
// draws at 0.05 Hz falls from 0.99 / 2.0 / 3.1 % (1 / 2 / 3 % noise; the raw FRF smoothed over
// ±¾ ζf, a window that could not be wider without flattening the peak) to 0.35 / 0.70 / 1.1 %.
inline constexpr int kSmoothingOrder = 4;
double smoothing_half_window_Hz(const FrfFit& fit) noexcept;

// How many samples (at the FRF's median spacing) span the sharpest fitted peak's half-power band
// 2ζ·f_n. Below kMinSamplesPerBandwidth the residual's window is kCoarseWindowFactor times wider
// (±24ζf): a coarsely sampled peak leaves too few samples in ±3ζf to average the noise out of
// the limit, so the lobes read the fit and only what of the residual varies slower than the
// peaks (a mode above the band, the fixture). Measured, 50 draws at 0.25 Hz (12 samples across
// a 150 Hz peak of ζ = 0.01), worst error at 1 / 2 / 3 % noise: ±3ζf 1.05 / 2.05 / 3.05 %,
// ±24ζf 0.54 / 1.08 / 1.62 % (20 draws), the fitted modes alone 0.56 / 1.12 / 1.68 %.
inline constexpr double kMinSamplesPerBandwidth = 20.0;
inline constexpr double kCoarseWindowFactor = 8.0;
double samples_per_bandwidth(const Frf& frf, const FrfFit& fit);

// Σ of the FRFs (each on its own grid) on the union of their bands' overlap: the grid of the
// first, restricted to where every other is measured.
Frf sum_frfs(const std::vector<Frf>& frfs);

}  // namespace lathectl::dynamics
