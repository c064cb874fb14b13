#pragma once
// System C's study: the template copied by the tracer slide (linear or nonlinear model, optionally
// both), the profile errors δx(y), δy(x) per feature, the closed-form check, report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::io {

RunOutput run_system_c(const Scenario& sc);

}  // namespace lathectl::io
