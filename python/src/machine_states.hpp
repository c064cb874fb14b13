#pragma once
// The machine objects' C++ side: one state per Python object (the machine, the inputs it keeps
// between calls as HAL pins keep theirs, the outputs' view alive now, the scenario it was made
// from), shared by the binding files and the test helpers (machines_testing.cpp).
#include <pybind11/pybind11.h>

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::python::machines {

namespace py = pybind11;

// The scenario `system` of `cls` (e.g. "E", "AdaptiveMachine") read as lathectl.run reads it;
// InputError at its `system` key when it is another system's.
io::Scenario scenario_of(const std::optional<std::string>& text, const std::string& label,
                         const char* system, const char* cls);

struct SlideState : std::enable_shared_from_this<SlideState> {
  control::SlideMachine m;
  control::SlideMachine::Input in;
  PyObject* view = nullptr;  // the outputs' object alive now (borrowed; it clears this)
  std::string name;
  double start_force_N = 0.0;  // the rig's nominal force, where start() starts from
  std::shared_ptr<const io::Scenario> sc;
};

struct GaugeState : std::enable_shared_from_this<GaugeState> {
  control::GaugeMachine m;
  control::GaugeMachine::Input in;
  PyObject* view = nullptr;
  std::string name;
  std::array<double, 4> rate_factor{1.0, 1.0, 1.0, 1.0};  // each command's removal rate / a
  double removal_m_per_s = 0.0;
  std::shared_ptr<const io::Scenario> sc;
};

struct AdaptiveState : std::enable_shared_from_this<AdaptiveState> {
  control::AdaptiveMachine m;
  control::AdaptiveMachine::Input in;
  control::AdaptiveMachine::Output out;  // kept between calls, as the HAL component's pins
  PyObject* view = nullptr;
  std::string name, load_unit;
  std::shared_ptr<const io::Scenario> sc;
};

struct ModulationState : std::enable_shared_from_this<ModulationState> {
  control::ModulationMachine m;
  control::ModulationMachine::Input in;
  control::ModulationMachine::Servo servo;
  PyObject* view = nullptr;
  std::string name;
  std::shared_ptr<const io::Scenario> sc;
};

// Test helpers (machines_testing.cpp): the rig's machine parameters against an object's, and
// the same inputs through a C++ loop.
void bind_testing(py::module_& m);

}  // namespace lathectl::python::machines
