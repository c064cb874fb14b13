#pragma once
// The rigs' names (namespace sim) for the sensor faults, which live in the core
// (sensors/faults.hpp) because the plant (cutting/lathe_plant.hpp) injects them too.

#include "lathectl/sensors/faults.hpp"

namespace lathectl::sim {
using sensors::FaultInjector;
using sensors::SensorFault;
}  // namespace lathectl::sim
