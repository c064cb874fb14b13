#pragma once
// Design formulas of seed 004 and the handbook tool-life relation:
//   V_opt = V_p · (S_p / S_cur)^{y_v}                       seed 004, optimal cutting speed
//   T = (Cv / (V · t^xv · s^yv))^{1/m}                      extended Taylor (handbook) [min]
//   V_T = Cv / (T^m · t^xv · s^yv)                          speed for a target life [m/min]
//   s = F / n                                               feed per revolution [mm/rev]
// Shop units throughout (m/min, mm/rev, mm, min, mm/min, rpm), as in the handbook.

namespace lathectl::design {

// Throws std::invalid_argument on non-positive inputs.
double optimal_speed(double V_p_m_per_min, double S_p_mm_per_rev, double y_v,
                     double S_cur_mm_per_rev);
double tool_life_min(double Cv, double m, double xv, double yv, double V_m_per_min, double depth_mm,
                     double feed_mm_per_rev);
double speed_for_life(double Cv, double m, double xv, double yv, double life_min, double depth_mm,
                      double feed_mm_per_rev);
double feed_per_rev(double feed_rate_mm_per_min, double spindle_rpm);

}  // namespace lathectl::design
