#pragma once
// System A's study: the scenario's run, its comparison and sweep, metrics, claims, report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/a_pulse_feed/metrics.hpp"
#include <nlohmann/json.hpp>

namespace lathectl::systems::a_pulse_feed {

io::RunOutput run(const io::Scenario& sc);
// The run's metrics as summary.json names them (what lathectl_slide_plant writes too).
nlohmann::json metrics_json(const Metrics& m);

}  // namespace lathectl::systems::a_pulse_feed
