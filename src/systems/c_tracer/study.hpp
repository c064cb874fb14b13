#pragma once
// System C's study: the template copied by the tracer slide (linear or nonlinear model, optionally
// both), the profile errors δx(y), δy(x) per feature, the closed-form check, report.

#include <cstddef>

#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::c_tracer {

io::RunOutput run(const io::Scenario& sc);
// The same with a budget of kept cone rows other than TracerMetrics::kKeptRows (a test: 0 takes
// the waviness from a second run of the rig, which must give the same numbers).
io::RunOutput run(const io::Scenario& sc, std::size_t kept_rows);

}  // namespace lathectl::systems::c_tracer
