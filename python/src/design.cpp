// lathectl.design.<name>: the design calculators (to be written).
#include "bindings.hpp"

namespace lathectl::python {
void bind_design(py::module_&) {}
}  // namespace lathectl::python
