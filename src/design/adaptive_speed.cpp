#include "lathectl/design/adaptive_speed.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace lathectl::design {

namespace {
std::string show(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}
// A quantity (speed, feed, depth, life, coefficient): finite and > 0.
void require_positive(double x, const char* name) {
  if (!(x > 0.0) || !std::isfinite(x))
    throw std::invalid_argument(std::string(name) + " must be a finite number > 0, got " + show(x));
}
// An exponent of the tool-life law: finite and ≥ 0 (0 is a handbook value, e.g. no depth term;
// the material file accepts the same range).
void require_exponent(double x, const char* name) {
  if (!(x >= 0.0) || !std::isfinite(x))
    throw std::invalid_argument(std::string(name) + " must be a finite exponent >= 0, got " +
                                show(x));
}
void require_taylor(double Cv, double m, double xv, double yv, double depth_mm,
                    double feed_mm_per_rev) {
  require_positive(Cv, "Cv");
  require_positive(m, "m");
  require_exponent(xv, "xv");
  require_exponent(yv, "yv");
  require_positive(depth_mm, "depth t [mm]");
  require_positive(feed_mm_per_rev, "feed s [mm/rev]");
}
}  // namespace

double optimal_speed(double V_p_m_per_min, double S_p_mm_per_rev, double y_v,
                     double S_cur_mm_per_rev) {
  require_positive(V_p_m_per_min, "computed speed V_p [m/min]");
  require_positive(S_p_mm_per_rev, "computed feed S_p [mm/rev]");
  require_exponent(y_v, "y_v");
  require_positive(S_cur_mm_per_rev, "current feed S [mm/rev]");
  return V_p_m_per_min * std::pow(S_p_mm_per_rev / S_cur_mm_per_rev, y_v);
}

double tool_life_min(double Cv, double m, double xv, double yv, double V_m_per_min, double depth_mm,
                     double feed_mm_per_rev) {
  require_taylor(Cv, m, xv, yv, depth_mm, feed_mm_per_rev);
  require_positive(V_m_per_min, "cutting speed V [m/min]");
  const double ratio = Cv / (V_m_per_min * std::pow(depth_mm, xv) * std::pow(feed_mm_per_rev, yv));
  return std::pow(ratio, 1.0 / m);
}

double speed_for_life(double Cv, double m, double xv, double yv, double life_min, double depth_mm,
                      double feed_mm_per_rev) {
  require_taylor(Cv, m, xv, yv, depth_mm, feed_mm_per_rev);
  require_positive(life_min, "tool life T [min]");
  return Cv / (std::pow(life_min, m) * std::pow(depth_mm, xv) * std::pow(feed_mm_per_rev, yv));
}

double feed_per_rev(double feed_rate_mm_per_min, double spindle_rpm) {
  require_positive(feed_rate_mm_per_min, "feed rate F [mm/min]");
  require_positive(spindle_rpm, "spindle speed n [rpm]");
  return feed_rate_mm_per_min / spindle_rpm;
}

}  // namespace lathectl::design
