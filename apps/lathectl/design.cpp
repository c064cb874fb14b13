// `lathectl design CALCULATOR`: the papers' design formulas. Each calculator is one file
// (design_<name>.cpp) holding the table of its inputs and outputs; this is the list of them.
#include <vector>

#include "cli.hpp"

namespace lathectl::cli {

const std::vector<const Calculator*>& calculators() {
  static const std::vector<const Calculator*> all{&kPulseRegulator, &kAdaptiveSpeed,
                                                  &kPlannedMode, &kGauge, &kTracer,
                                                  &kModulation};
  return all;
}

void add_design(CLI::App& app, Commands& out) {
  auto* design = app.add_subcommand("design", "Design calculators from the papers' formulas");
  design->require_subcommand(1);
  for (const auto* c : calculators()) c->add(*design->add_subcommand(c->name, c->description), out);
}

}  // namespace lathectl::cli
