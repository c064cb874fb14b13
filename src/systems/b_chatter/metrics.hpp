#pragma once
// What system B's study measures on a run of the rig (the steady window of the cut), and the
// linear stability limits of the set-up's delay equation at a cutting position.

#include <limits>
#include <string>

#include "systems/b_chatter/rig.hpp"

namespace lathectl::b_chatter {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What one run of the rig answers, measured over the last 30 % of the cut (the steady state).
struct Run {
  sim::RigB rig;
  std::string label;
  double vibration_um = 0.0;         // chatter band: peak |y_highpass|
  double forced_um = 0.0;            // below the band: half the swing of y − y_highpass
  double static_um = 0.0;            // mean y: the bending by unbalanced radial forces
  double chatter_Hz = kNaN;          // zero crossings of y_highpass
  double feed_mean[2] = {0.0, 0.0};  // per turret over the cut [mm/min]
  double cut_power_W = 0.0, cut_power_measured_W = 0.0;
  double one_out_share = 0.0;  // share of the window with one turret out of the cut
  // Depth division: the revolutions (+½) back of tool 1's pass tool 2 met, over the window.
  double delay_min_rev = kNaN, delay_max_rev = kNaN;
  double t0 = 0.0, t1 = 0.0;   // the window
};

// Fills r's measures from its rig's recording. The chatter frequency only when the vibration is
// above the dead zone (else it is noise).
void measure(Run& r, bool twin, double dead_zone_um);

// The linear limits of the loops at a cutting position, as chip per revolution at the program's
// speed: one tool (τ, +μ) and twin turrets in feed division (τ/2, −μ, gains added).
struct Limits {
  double single_feed = kNaN, twin_feed = kNaN, chatter_Hz = kNaN;
};
Limits linear_limits(const sim::RigBConfig& b, double x_mm, double rpm, int points = 20000);

}  // namespace lathectl::b_chatter
