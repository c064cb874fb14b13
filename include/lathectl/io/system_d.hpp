#pragma once
// System D's study: calibration of the full transducer against the seed's linearisation,
// full-model parts against the linear predictions (inside and outside their range), the
// linearised Monte Carlo of finished sizes (Cp/Cpk), the check of (25), report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::io {

RunOutput run_system_d(const Scenario& sc);

}  // namespace lathectl::io
