// lathectl.lobes, lathectl.read_frf, lathectl.fit_modes (to be written).
#include "bindings.hpp"

namespace lathectl::python {
void bind_lobes(py::module_&) {}
}  // namespace lathectl::python
