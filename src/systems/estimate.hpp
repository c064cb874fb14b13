#pragma once
// What a scenario will cost before it runs (`lathectl check`, lathectl/io/estimate.hpp): its
// system's estimate, as the registry's entry points at it (src/systems/<folder>/estimate.cpp).

#include "lathectl/io/estimate.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems {

using io::duration_text;
using io::RunEstimate;
using io::size_text;
using io::summary_text;

RunEstimate estimate(const io::Scenario& sc);

}  // namespace lathectl::systems
