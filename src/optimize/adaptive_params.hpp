#pragma once
// System E's machine side as `optimize` runs it in the loop (Options::adaptive), defined in
// predict.cpp. Its own header, not optimize.hpp: the machine's header (control/adaptive_machine.hpp)
// is then compiled by predict.cpp and its test alone, not by every file of the optimiser, the
// program and the tests that include optimize.hpp.

#include "lathectl/control/adaptive_machine.hpp"
#include "optimize/optimize.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::optimize {

// The scenario's, derived by e_adaptive::machine_params as the rig and lathectl_adaptive derive it.
control::AdaptiveMachine::Params adaptive_machine_params(const systems::e_adaptive::Settings& e,
                                                         const Options& opt);

}  // namespace lathectl::optimize
