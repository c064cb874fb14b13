#pragma once
// System C's study: the template copied by the tracer slide (linear or nonlinear model, optionally
// both), the profile errors δx(y), δy(x) per feature, the closed-form check, report.

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::c_tracer {

io::RunOutput run(const io::Scenario& sc);

}  // namespace lathectl::systems::c_tracer
