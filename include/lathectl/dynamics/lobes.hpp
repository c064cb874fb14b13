#pragma once
// Regenerative chatter in turning with one delay (the previous revolution), and its stability
// lobes, two independent ways (system B, layer 1).
//
// Modes m = 1..M, each with stiffness k_m, damping ratio ζ_m, natural frequency ω_m and direction
// at θ_m to the chip thickness; the oriented FRF in the chip-thickness direction
//   Φ(jω) = Σ cos²θ_m / (k_m·(1 − r_m² + 2jζ_m·r_m)),  r_m = ω/ω_m.
// Chip thickness h = h0 − [y(t) − y(t − τ)], force F = K_f·b·h, τ = 60/n.
// Frequency domain (Tlusty, Tobias; Altintas, "Manufacturing Automation", ch. 3):
//   b_lim(ω) = −1/(2·K_f·Re Φ(jω))  where Re Φ < 0,
//   ε = 3π + 2·atan2(Im Φ, Re Φ),  n = 60·ω/(2π) / (N + ε/2π),  N = 0, 1, 2, ...
//   (from e^{−jωτ} = −Φ*/Φ, which makes b real). SDOF closed form: the minimum
//   b_crit = 2k·ζ(1+ζ)/(K_f·cos²θ) at ω = ω_n·√(1+2ζ).
// Semi-discretization (Insperger & Stépán, Int. J. Numer. Meth. Engng 61 (2004) 117–141):
//   ẋ = A·x + K_f·b·u·(y(t − τ) − y(t)) in modal state x = [q; q̇], y = vᵀx the displacement
//   along the chip thickness; over steps Δt = τ/m the delayed y is linearly interpolated and the
//   rest integrated exactly (matrix exponential); the map z_{i+1} = D·z_i with
//   z = [x_i, y_{i−1}, ..., y_{i−m}] (the force is rank one, so only y needs a history) is
//   stable when the spectral radius of D < 1, i.e. when none of the roots of its characteristic
//   polynomial lies outside the unit circle, which the argument principle counts in O(m) (see
//   lobes.cpp). The limit depth at a speed is found by bisection on b; a speed × depth chart
//   counts the unstable roots on a grid and bisects its boundary between grid depths.

#include <complex>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace lathectl::dynamics {

struct Mode {
  double stiffness_N_per_m = 1e7;
  double damping_ratio = 0.02;
  double natural_frequency_Hz = 500.0;
  double angle_rad = 0.0;  // to the chip-thickness direction
};

// A measured receptance along the chip thickness [m/N] (dynamics/frf.hpp: interpolation,
// smoothing, modal fit), frequencies strictly ascending.
struct Frf {
  std::vector<double> frequency_Hz;
  std::vector<std::complex<double>> receptance_m_per_N;
  // Optional modes the samples are read against (dynamics/frf.hpp, frf_at): between samples the
  // value is their FRF plus the samples' difference from it, interpolated — a lightly damped peak
  // keeps the shape of its fitted mode instead of a straight line between coarse samples.
  std::vector<Mode> baseline = {};
};

struct ChatterSystem {
  std::vector<Mode> modes;
  double kf_N_per_m2 = 1e9;  // K_f along the chip thickness [N/m²]
  // Measured receptances, already oriented to the chip thickness, added to the modes' Φ between
  // their measured frequencies. Only the frequency domain reads them (its band is then the
  // measured band, where every one is known); semi-discretization and the time domain need
  // modes (fit_modes) and refuse a system with measured FRFs.
  std::vector<Frf> frfs = {};
  // Process damping (frequency domain only; 0: none): the flank ploughing the wavy surface it has
  // just cut, linearised as a viscous damper along the chip thickness c = C·b/n [N·s/m], b the
  // depth [m], n the speed [rpm] — the equivalent coefficient K_sp·w·VB²/(4V) of the B rig's
  // indentation model (dynamics/twin_turret.hpp; Chiou & Liang, IJMTM 38 (1998)) with
  // w = b/sin κ and V = π·D·n/60, so C = 60·K_sp·VB²/(4π·D·sin κ). The structure then answers
  // Φ_c = Φ/(1 + jω·c·Φ); since c grows with the depth and falls with the speed, each lobe point
  // is the fixed point of the lobe equations in (b, n), and below the speed where no fixed point
  // exists the lobe is absent (stable at every depth).
  double process_damping_C = 0.0;
};

struct LobePoint {
  double speed_rpm = 0.0;
  double depth_m = 0.0;
  double chatter_Hz = 0.0;
};

struct Lobe {
  int N = 0;
  std::vector<LobePoint> points;  // ascending chatter frequency
  LobePoint minimum;              // lowest depth on this lobe within the speed range
  // The minimum lies inside the speed range (its grid neighbours on both sides are on the lobe
  // in range). False: the lobe leaves the range while still falling, and `minimum` is only the
  // lowest point at the range's edge, not the lobe's minimum.
  bool minimum_inside = true;
};

// A run of consecutive lobe segments (points k−1, k for k in [first, last)) along which the speed
// is strictly monotone: the segment holding a speed is found by binary search.
struct EnvelopeRun {
  std::size_t lobe = 0;
  std::size_t first = 0, last = 0;  // segment k joins points k − 1 and k
  bool ascending = true;            // speed rises with k
  double lo_rpm = 0.0, hi_rpm = 0.0;
};

struct FrequencyDomainResult {
  double critical_depth_m = 0.0;  // absolute stability limit
  double critical_chatter_Hz = 0.0;
  std::vector<Lobe> lobes;
  // The lobes cut into monotone runs (index_envelope), so envelope_depth costs
  // O(runs · log points) per query instead of O(points). Filled by frequency_domain_lobes.
  std::vector<EnvelopeRun> envelope_runs;
};

// Throws std::invalid_argument on an empty or invalid system.
FrequencyDomainResult frequency_domain_lobes(const ChatterSystem& sys, double min_rpm,
                                             double max_rpm, int max_lobes = 40,
                                             int frequency_points = 4000);
// The points frequency_domain_lobes would store over all its lobes, counted without storing
// them (O(frequency_points · modes)): its memory and time grow with this count, which a wide
// speed range of dense lobes makes billions (1–100 000 rpm on one 500 Hz mode: 10⁹, 24 GB).
double frequency_domain_point_count(const ChatterSystem& sys, double min_rpm, double max_rpm,
                                    int max_lobes = 40, int frequency_points = 4000);
// Limit depth at one speed from the lobes (lower envelope of all lobes at that speed): the least,
// over every lobe segment whose speeds bracket speed_rpm (ends included), of the depth linearly
// interpolated in speed; +inf where no segment does. Uses fd.envelope_runs when present (binary
// search per run) and scans every segment otherwise; both give bit-identical results.
double envelope_depth(const FrequencyDomainResult& fd, double speed_rpm);
// (Re)builds fd.envelope_runs from fd.lobes (after changing the lobes by hand).
void index_envelope(FrequencyDomainResult& fd);

// Semi-discretization (SD): the spectral radius of the SD map at (speed, depth) by a dense
// eigenvalue solve (O((2·modes + m)³); for checks), the number of its eigenvalues outside the
// unit circle by the argument principle (O(m·modes³); what the chart and the bisection use,
// see lobes.cpp), and the limit depth at a speed by bisection on "no root outside".
// interpolation_order: of the delayed displacement, 1 (the classic first-order SD), 3 or 5
// (see SdChartOptions below).
double spectral_radius_sd(const ChatterSystem& sys, double speed_rpm, double depth_m, int m = 30,
                          int interpolation_order = 1);
int sd_unstable_roots(const ChatterSystem& sys, double speed_rpm, double depth_m, int m = 30,
                      int interpolation_order = 1);
double sd_limit_depth(const ChatterSystem& sys, double speed_rpm, double depth_hi_m, int m = 30,
                      double rel_tol = 1e-3, int interpolation_order = 1);

// Semi-discretization stability chart: on a speed × depth grid, the number of the SD map's
// eigenvalues outside the unit circle (0: stable), and per speed the SD boundary: the lowest
// grid depth with a root outside, refined by bisection between it and the grid depth below to
// boundary_rel_tol. Steps per delay at speed n:
//   m = clamp(⌈(60/n)·f_ref·steps_per_period⌉, min_steps, max_steps),
// f_ref the highest frequency among the modes that can chatter on the chart (own SDOF limit
// 2kζ(1+ζ)/(K_f·cos²θ) below twice the chart's top depth). The delayed displacement is
// interpolated by a Lagrange polynomial through order + 1 history points (higher-order SD); the
// error falls as Δt^(order+1). Quintic at 7 steps per period is within ≈ 0.1 % of the exact
// (frequency-domain) limit (SdChart tests; at 5 steps per period 0.04 %).
// Per cell: one (2·modes + order + 1)² matrix exponential and a root count along the unit
// circle at ~4·m points, each a (2·modes)² complex determinant: the cost grows as m, not m³, as
// a dense eigenvalue solve of size 2·modes + m + 2 would (figures: docs/machine-file-reference.md).
struct SdChartOptions {
  int steps_per_period = 7;     // per period of f_ref (above)
  int min_steps = 20;           // per delay (one revolution)
  int max_steps = 4000;         // cap on m (the cost per cell grows as m)
  int interpolation_order = 5;  // of the delayed displacement: 1, 3 or 5 (quintic)
  double boundary_rel_tol = 1e-6;  // bisection of the boundary between grid depths
  unsigned threads = 0;         // 0: one per hardware thread
  // Called (from any worker thread, so it must be thread-safe) each time a speed is done.
  std::function<void(std::size_t done, std::size_t total)> on_speed_done;
};
struct SdChart {
  std::vector<double> speed_rpm;         // n_speeds, min..max inclusive
  std::vector<double> depth_m;           // n_depths, 0..max inclusive
  std::vector<int> steps;                // m used at each speed
  std::vector<int> unstable_roots;       // row-major [speed][depth]: SD eigenvalues with |μ| > 1
  std::vector<double> boundary_depth_m;  // per speed: the SD boundary (above); +inf if every
                                         // grid depth is stable
  [[nodiscard]] int unstable(std::size_t i_speed, std::size_t i_depth) const {
    return unstable_roots[i_speed * depth_m.size() + i_depth];
  }
};
// Throws std::invalid_argument on a bad system or grid. Runs on options.threads threads.
SdChart sd_stability_chart(const ChatterSystem& sys, double min_rpm, double max_rpm, int n_speeds,
                           double max_depth_m, int n_depths, const SdChartOptions& options = {});
// The m a chart up to max_depth_m uses at a speed.
int sd_steps_per_delay(const ChatterSystem& sys, double speed_rpm, double max_depth_m,
                       const SdChartOptions& options = {});

// Time domain, one delay, the tool leaving the cut when h < 0: returns the vibration amplitude
// (max |y| over a window) at the start and at the end, from a small initial disturbance.
struct TimeDomainResult {
  double amplitude_early_m = 0.0;
  double amplitude_late_m = 0.0;
  bool grew = false;
};
TimeDomainResult time_domain(const ChatterSystem& sys, double speed_rpm, double depth_m,
                             double feed_m, double duration_s, int steps_per_period = 100);

}  // namespace lathectl::dynamics
