#pragma once
// What system A's registry entry (src/systems/registry.cpp) points at besides its study's run.

#include <filesystem>
#include <string>

#include "lathectl/io/estimate.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::a_pulse_feed {

// Its study's cost before it runs (estimate.cpp).
io::RunEstimate estimate(const io::Scenario& sc);

}  // namespace lathectl::systems::a_pulse_feed
