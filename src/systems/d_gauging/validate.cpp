// System D's cross-checks once the whole scenario is read: the transducer configured once as a
// probe, the allowance against its free amplitude, the threshold against the signal's safe range.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl::systems::d_gauging {

namespace {
// A number as a user wrote it (shortest form, no trailing zeros).
std::string fmt_number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

std::string mv(double v) {
  return fmt_number(std::round(v * 1e3) / 1e3);
}  // V, to the mV
std::string um(double m) {
  return fmt_number(std::round(m * 1e7) / 10.0);
}  // µm, to 0.1

}  // namespace

void validate(const io::Scenario& sc) {
  const auto& d = sc.get<Settings>();
  sensors::VibroContactGauge probe;
  configure_transducer(sc, probe);
  // The transducer reads nothing above its free amplitude: found here, not after a run.
  if (d.process.allowance_m > probe.free_amplitude_m())
    sc.keys->fail("process.allowance_um",
                  fmt_number(d.process.allowance_m * 1e6) +
                      " µm exceeds the largest allowance this transducer can measure, A0 = " +
                      fmt_number(probe.free_amplitude_m() * 1e6) + " µm");
  // The relay must see the signal rise through its threshold: found here, not after a
  // cut that never ends.
  const ThresholdPlan plan = plan_threshold(d, sc.run.step_s);
  if (plan.safe() || d.force_threshold) return;
  const auto& r = plan.range;
  const bool below = plan.threshold_V < r.low_V;
  const std::string why =
      "threshold S_th = " + mv(plan.threshold_V) + " V (" + d.threshold + ") lies " +
      (below ? "below " + mv(r.low_V) + " V, the probe's bounce floor (" + mv(r.floor_V) +
                   " V from x = " + um(r.floor_start_m) + " µm on)"
             : "above " + mv(r.high_V) + " V, the free signal (" + mv(r.free_V) + " V)") +
      " with its margin (ripple " + mv(r.ripple_V) + " V + 4σ noise " + mv(4.0 * r.noise_sigma_V) +
      " V): the relay would never trip; the safe range ends at target_um = " +
      um(plan.largest_target_m) + " (set gauge.force_threshold = true to run into the backstop)";
  sc.keys->fail(d.threshold == "given" ? "gauge.threshold_V" : "process.target_um", why);
}

}  // namespace lathectl::systems::d_gauging
