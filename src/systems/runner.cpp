#include "lathectl/io/errors.hpp"
#include "systems/registry.hpp"

namespace lathectl::systems {

io::RunOutput run_scenario(const io::Scenario& sc) {
  const System* s = find(sc.system);
  if (!s) throw io::InputError(sc.file + ": system '" + sc.system + "' is not implemented");
  io::RunOutput out = s->run(sc);
  io::finish_run(sc, out);
  return out;
}

}  // namespace lathectl::systems
