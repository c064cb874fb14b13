#pragma once
// The host's name for the one parallel-for, which lives in the core (core/parallel.hpp) because
// dynamics/lobes.cpp needs it too.

#include "lathectl/core/parallel.hpp"

namespace lathectl::sim {
using core::parallel_for;
}  // namespace lathectl::sim
