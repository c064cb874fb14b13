#pragma once
// System D's study: calibration of the full transducer against the seed's linearisation,
// full-model parts against the linear predictions (inside and outside their range), the
// linearised Monte Carlo of finished sizes (Cp/Cpk), the check of (25), report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::d_gauging {

io::RunOutput run(const io::Scenario& sc);

}  // namespace lathectl::d_gauging
