#pragma once
// Transitional (issue 12): the per-system section readers not yet moved into systems/<x>/.

#include <memory>

#include "lathectl/io/scenario.hpp"

namespace lathectl::io {
std::unique_ptr<SystemSettings> read_legacy(TableReader& root, Scenario& sc,
                                            const MaterialLibrary& lib);
}  // namespace lathectl::io
