#pragma once
// What makes cutting forces vary (seeds 000, 004): allowance (depth) variation — steps along the
// part, runout once per revolution (eccentric blank), random allowance — hardness along the part,
// and tool wear growing with cutting time.
//
//   depth(x, φ) = depth_profile(x) + runout · sin φ + r(x)          [mm]
//     depth_profile: piecewise constant steps, each entered over a ramp of `step_ramp_mm`
//     r(x): Ornstein–Uhlenbeck process in travel x, σ = random_sigma, correlation length L,
//           advanced exactly: r ← r·e^(−Δx/L) + σ·sqrt(1 − e^(−2Δx/L))·N(0,1)
//   strength_factor(x): piecewise linear between the given points (1 outside none given)
//   VB(t_cut) = VB0 + rate · t_cut;  wear_factor = 1 + force_gain · VB       [mm; 1/mm]
//
// x is the tool's travel along its feed path [mm]; φ the spindle angle [rad]; t_cut the time in
// cut [s]. Measurement noise lives with each sensor, seeded from the scenario.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace lathectl::cutting {

struct ProfilePoint {
  bool operator==(const ProfilePoint&) const = default;
  double at_mm = 0.0;
  double value = 0.0;
};

struct DisturbanceParams {
  bool operator==(const DisturbanceParams&) const = default;
  double depth_mm = 1.0;                  // nominal depth of cut (allowance)
  std::vector<ProfilePoint> depth_steps;  // at_mm → new depth_mm, ascending
  double step_ramp_mm = 0.5;              // travel over which a step is entered
  double runout_mm = 0.0;                 // depth amplitude per revolution
  double random_sigma_mm = 0.0;           // random allowance σ
  double random_correlation_mm = 5.0;     // its correlation length
  std::vector<ProfilePoint> hardness;     // at_mm → strength factor, ascending
  double wear_VB0_mm = 0.0;               // initial flank wear
  double wear_rate_mm_per_min = 0.0;      // flank wear growth per minute in cut
  double wear_force_gain_per_mm = 0.0;    // force factor growth per mm of VB
  std::uint64_t seed = 1;
};

struct LocalCut {
  double depth_mm = 0.0;
  double strength_factor = 1.0;
  double wear_factor = 1.0;
  double flank_wear_mm = 0.0;
};

class Disturbances {
 public:
  void configure(const DisturbanceParams& p);  // throws std::invalid_argument
  // Advances the random allowance (OU process) to travel x and returns it [mm].
  double random_allowance_mm(double travel_mm) noexcept;
  // Advances the random allowance to travel x (monotone or not) and evaluates the local cut.
  LocalCut at(double travel_mm, double spindle_angle_rad, double time_in_cut_s) noexcept;
  // Depth of the deterministic profile alone (no runout, no random part).
  [[nodiscard]] double depth_profile(double travel_mm) const noexcept;
  [[nodiscard]] double strength_factor(double travel_mm) const noexcept;
  // Force factor of flank wear after t_cut seconds in cut.
  [[nodiscard]] double wear_factor(double time_in_cut_s) const noexcept;
  // Travel of the first step or hardness change (where the first disturbance begins), or +inf.
  [[nodiscard]] double first_change_mm() const noexcept;

 private:
  [[nodiscard]] double hardness_between(double travel_mm) const noexcept;
  DisturbanceParams p_{};
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> normal_{0.0, 1.0};
  double random_mm_ = 0.0;
  double last_x_ = 0.0;
};

// The per-step path in the header (issue 45 item 6): a rig asks it every step, and out of line
// each call stored and reloaded the rig's state around it. What a part without a term asks
// (no random allowance, no hardness points) costs a compare.
inline LocalCut Disturbances::at(double x, double phi, double t_cut) noexcept {
  if (p_.random_sigma_mm > 0.0)
    (void)random_allowance_mm(x);
  else
    last_x_ = x;  // what random_allowance_mm does without a random allowance
  LocalCut c;
  const double runout = p_.runout_mm > 0.0 ? p_.runout_mm * std::sin(phi) : 0.0;
  c.depth_mm = std::max(depth_profile(x) + runout + random_mm_, 0.0);
  c.strength_factor = strength_factor(x);
  c.flank_wear_mm = p_.wear_VB0_mm + p_.wear_rate_mm_per_min * t_cut / 60.0;
  c.wear_factor = wear_factor(t_cut);
  return c;
}

inline double Disturbances::depth_profile(double x) const noexcept {
  double depth = p_.depth_mm;
  for (const auto& s : p_.depth_steps) {
    if (x <= s.at_mm) break;
    const double ramp =
        p_.step_ramp_mm > 0.0 ? std::min((x - s.at_mm) / p_.step_ramp_mm, 1.0) : 1.0;
    depth += (s.value - depth) * ramp;
  }
  return depth;
}

inline double Disturbances::strength_factor(double x) const noexcept {
  return p_.hardness.empty() ? 1.0 : hardness_between(x);
}

inline double Disturbances::wear_factor(double t_cut) const noexcept {
  return 1.0 +
         p_.wear_force_gain_per_mm * (p_.wear_VB0_mm + p_.wear_rate_mm_per_min * t_cut / 60.0);
}

}  // namespace lathectl::cutting
