// System C's cost before it runs (`lathectl check`; lathectl/io/estimate.hpp): its study's
// runs, counted as study.cpp makes them, times the cost per step measured on the examples.
#include "systems/c_tracer/entry.hpp"
#include "systems/c_tracer/settings.hpp"

namespace lathectl::systems::c_tracer {

namespace {
constexpr io::StepCosts kCosts{3.0e-6, 60.0};
}  // namespace

io::RunEstimate estimate(const io::Scenario& sc) {
  io::RunEstimate e = io::report_only();
  const auto& s = sc.get<Settings>();
  const double runs = s.compare.empty() ? 1.0 : 2.0;
  // C traces the whole template whatever run.duration_s says: its length at the feed speed.
  io::Scenario traced = sc;
  const auto& r = s.rig;
  const double v = r.feed_m_per_rev * r.spindle_rpm / 60.0;
  if (v > 0.0 && r.profile.xs().size() >= 2)
    traced.run.duration_s = (r.profile.xs().back() - r.profile.xs().front()) / v;
  io::add_rig_runs(e, traced, runs, 1.0, kCosts, runs);
  return e;
}

}  // namespace lathectl::systems::c_tracer
