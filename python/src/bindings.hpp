#pragma once
// What the Python module's binding files share (module.cpp lists them): the GIL released around
// long work with Ctrl-C still stopping it, lathectl's errors as Python's, JSON as Python objects.
// Each binding file adds its names to the module in one function declared here.
#include <pybind11/pybind11.h>

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>

namespace lathectl::io {
struct Scenario;
}

namespace lathectl::python {

namespace py = pybind11;

// The module's names, one binding file each.
void bind_run(py::module_& m);       // run.cpp: run, check, the Run object
void bind_lobes(py::module_& m);     // lobes.cpp: lobes, read_frf, fit_modes
void bind_design(py::module_& m);    // design.cpp: the design calculators
void bind_machines(py::module_& m);  // machines.cpp: the machine-side objects

// lathectl.InputError (a ValueError), created by module.cpp.
PyObject* input_error_type();

// A scenario read and validated by the same reader as `lathectl run` (run.cpp): `text` given, the
// text the package made of a dict, `label` its name in messages and the directory its relative
// files are found in; else `label` is the file. Throws io::InputError.
io::Scenario read_scenario(const std::optional<std::string>& text, const std::string& label);

// A JSON value as the Python object json.loads gives for its text (the same keys and numbers).
py::object to_python(const nlohmann::json& j);

// Runs `work` with the GIL released and a progress line (`what`; drawn on stderr only when
// `progress`) whose simulations poll for Ctrl-C: on the main thread, every update checks Python's
// signals, and a KeyboardInterrupt (or whatever the SIGINT handler raised) stops the work by an
// exception and is raised here once the work has unwound. lathectl's InputError becomes
// lathectl.InputError, a filesystem error an OSError, anything else a RuntimeError.
void without_gil(const std::string& what, bool progress, const std::function<void()>& work);

}  // namespace lathectl::python
