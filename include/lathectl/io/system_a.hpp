#pragma once
// System A's study: the scenario's run, its comparison and sweep, metrics, claims, report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::io {

RunOutput run_system_a(const Scenario& sc);

}  // namespace lathectl::io
