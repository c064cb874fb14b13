#pragma once
// Internal to the chatter model (lobes.cpp: the frequency domain; lobes_sd.cpp: semi-discretization
// and the time domain): the checks of a ChatterSystem, each throwing std::invalid_argument.

#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::dynamics::detail {

void check(const ChatterSystem& sys);
// Semi-discretization and the time domain integrate modes: a measured FRF must be fitted first.
void check_modal(const ChatterSystem& sys);

}  // namespace lathectl::dynamics::detail
