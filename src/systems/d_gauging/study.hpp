#pragma once
// System D's study: calibration of the full transducer against the seed's linearisation,
// full-model parts against the linear predictions (inside and outside their range), the
// linearised Monte Carlo of finished sizes (Cp/Cpk), the check of (25), report.

#include <cstddef>

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::d_gauging {

io::RunOutput run(const io::Scenario& sc);
// The same with another budget of kept linearised parts than LinearParts::kKeptParts (a
// test: beyond it the parts are machined again for each pass, which must give the same numbers).
io::RunOutput run(const io::Scenario& sc, std::size_t kept_parts);

}  // namespace lathectl::systems::d_gauging
