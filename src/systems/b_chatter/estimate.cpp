// System B's cost before it runs (`lathectl check`; lathectl/io/estimate.hpp): its study's
// runs, counted as study.cpp makes them, times the cost per step measured on the examples.
#include "systems/b_chatter/entry.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl::systems::b_chatter {

namespace {
constexpr io::StepCosts kCosts{0.40e-6, 130.0};
}  // namespace

io::RunEstimate estimate(const io::Scenario& sc) {
  io::RunEstimate e = io::report_only();
  const auto& s = sc.get<Settings>();
  const bool modulated = s.rig.source != control::ModulationSource::None;
  const double main = modulated && s.compare ? 2.0 : 1.0;
  io::add_rig_runs(e, sc, main, 2.0, kCosts, main);
  if (!s.sweep_feed_mm_per_rev.empty())  // with and without modulation at each feed, 4 at a time
    io::add_rig_runs(e, sc,
                     (modulated ? 2.0 : 1.0) * static_cast<double>(s.sweep_feed_mm_per_rev.size()),
                     4.0, kCosts, 0.0);
  return e;
}

}  // namespace lathectl::systems::b_chatter
