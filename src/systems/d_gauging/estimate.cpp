// System D's cost before it runs (`lathectl check`; lathectl/io/estimate.hpp): its study's
// runs, counted as study.cpp makes them, times the cost per step measured on the examples.
#include <cmath>

#include "systems/d_gauging/entry.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl::systems::d_gauging {

namespace {
constexpr double kDFullStep = 0.40e-6;     // the full transducer model, per step of a part
constexpr double kDTripFraction = 0.2;     // a full-model part ends at the trip: about this share
                                           // of run.duration_s on the examples (a gauge that never
                                           // trips runs every part to run.duration_s)
constexpr double kDLinearPartPass = 6e-6;  // the linearised model, per part and pass
constexpr double kDPartRowBytes = 42.0;    // channels.csv of D: one row a part
}  // namespace

io::RunEstimate estimate(const io::Scenario& sc) {
  io::RunEstimate e = io::report_only();
  const auto& s = sc.get<Settings>();
  // Full model: the recorded part, the one without noise, the noisy parts and (calibrated_
  // dynamic) up to calibration_parts_max more, each at most run.duration_s long, on all cores.
  const double full =
      2.0 + static_cast<double>(s.full_parts) +
      (s.threshold == "calibrated_dynamic" ? static_cast<double>(s.calibration_parts_max) : 0.0);
  const double steps = std::ceil(sc.run.duration_s / sc.run.step_s);
  e.simulated_steps = full * steps;
  const double full_cpu = full * steps * kDTripFraction * kDFullStep;
  // Linearised: the calibration's parts and the Monte Carlo's, three passes over each.
  const double linear = 2.0 * static_cast<double>(s.parts);
  const double linear_cpu = 3.0 * linear * kDLinearPartPass;
  e.parts = linear / 2.0 + static_cast<double>(s.full_parts);
  e.cpu_s = full_cpu + linear_cpu;
  e.wall_s = e.cpu_s / io::estimate_cores();
  e.output_bytes += static_cast<double>(s.parts) * kDPartRowBytes +
                    (sc.run.duration_s / sc.run.record_interval_s) * 120.0;
  e.breakdown = io::count_text(static_cast<double>(s.parts)) + " linearised parts; " +
                io::count_text(full) + " full-model parts × up to " + io::count_text(steps) +
                " steps (about a fifth of that when the gauge trips)";
  return e;
}

}  // namespace lathectl::systems::d_gauging
