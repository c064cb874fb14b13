#pragma once
// A vibro-contact gauge designed from its measured calibration instead of its coil and probe
// physics (seed 003, issue 48 item 3). A shop measures its transducer's filtered voltage at
// known allowances x (setting masters); (20) says the voltage is about K·(B0/q1 − x) for
// 0 ≤ x ≤ A0 and leaves that line beyond A0, where the part no longer clips the probe's swing
// (the full model's bounce floor, sensors/vibro_contact_gauge.hpp). From the points:
//
//   the line: least squares over the points with x ≤ A0; K = −slope, B0/q1 = its zero crossing;
//   the noise σ_n: robust, from the points alone, before any line: each interior point's
//     deviation from the chord of its two neighbours, r_i = V_i − (w_l·V_{i−1} + w_r·V_{i+1})
//     (w_l, w_r the chord's weights at x_i), divided by sqrt(1 + w_l² + w_r²) (its standard
//     deviation in units of σ for independent noise), and σ_n = 1.4826·median|r_i| (the normal
//     distribution's median absolute deviation). A line's chord residual is 0, so it measures
//     the noise; a kink (where the curve leaves the line) touches one point only, which the
//     median ignores;
//   A0: the largest measured x for which the line fitted to all points in [0, x] keeps every
//     residual within kLeaveSigmas·σ_n. Why 4: with independent normal noise, a point lies
//     beyond 4σ with probability 6.3e-5, so over 100 points the rule cuts the true line short by
//     noise with a probability under 0.7 %, while a departure of more than about 4σ_n (in size:
//     4σ_n/K) is seen. Noise-free points (σ_n = 0) are judged to 1e-9 of their voltage span.
//   the fit quality: the line's residual σ = sqrt(Σr²/(m − 2)) over its m points and R².

#include <cstddef>
#include <span>

namespace lathectl::design {

struct CalibrationPoint {
  double allowance_m = 0.0;  // x of (20)
  double voltage_V = 0.0;    // the filtered signal measured there
};

inline constexpr double kLeaveSigmas = 4.0;
inline constexpr std::size_t kMinCalibrationPoints = 5;

struct CalibrationFit {
  double gain_V_per_m = 0.0;      // K
  double intercept_m = 0.0;       // B0/q1, the line's zero crossing
  double free_amplitude_m = 0.0;  // A0: where the measured curve leaves the line
  double noise_sigma_V = 0.0;     // σ_n, from the chord residuals
  double residual_sigma_V = 0.0;  // the line's residual σ over [0, A0]
  double r_squared = 0.0;
  std::size_t points_on_line = 0, points = 0;
  bool leaves = false;  // a measured point beyond A0 (else A0 is the last point: at least that)
};

// Throws std::invalid_argument: fewer than kMinCalibrationPoints points, x not strictly
// ascending or negative, a voltage that does not fall along the line (K ≤ 0).
CalibrationFit fit_calibration(std::span<const CalibrationPoint> points);

}  // namespace lathectl::design
