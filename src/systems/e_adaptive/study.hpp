#pragma once
// System E's study: the scenario's run and the controllers it is compared with, metrics,
// claims (force held, productivity order, tool life against plan, sensor faults), report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::e_adaptive {

io::RunOutput run(const io::Scenario& sc);

}  // namespace lathectl::systems::e_adaptive
