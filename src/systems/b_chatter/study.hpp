#pragma once
// System B's study: the twin-turret cut with and without the modulated feed, the linear limits
// that explain where modulation can help, the van der Pol check of the quenching condition, an
// optional sweep over the feed, metrics, claims and report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::b_chatter {

io::RunOutput run(const io::Scenario& sc);

}  // namespace lathectl::systems::b_chatter
