#include "systems/estimate.hpp"

#include "systems/registry.hpp"

namespace lathectl::systems {

RunEstimate estimate(const io::Scenario& sc) {
  const System* s = find(sc.system);
  return s && s->estimate ? s->estimate(sc) : io::report_only();
}

}  // namespace lathectl::systems
