#pragma once
// System A's study: the scenario's run, its comparison and sweep, metrics, claims, report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::a_pulse_feed {

io::RunOutput run(const io::Scenario& sc);

}  // namespace lathectl::systems::a_pulse_feed
