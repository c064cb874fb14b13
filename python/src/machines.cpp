// The machine-side objects for users' own loops (to be written).
#include "bindings.hpp"

namespace lathectl::python {
void bind_machines(py::module_&) {}
}  // namespace lathectl::python
