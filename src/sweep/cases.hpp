#pragma once
// The cases of a sweep: drawn up front from the spec (grid points in the spec's order, the last
// key fastest, each crossed with every random sample), each one the whole scenario as TOML text
// with the case's values applied and the scenario's own studies ([study], [sweep], [compare])
// removed: one case, one run.

#include <cstdint>
#include <string>
#include <vector>

#include "lathectl/io/materials.hpp"
#include "sweep/spec.hpp"

namespace lathectl::sweep {

// The tables a case removes from its scenario: the system's own studies.
inline constexpr const char* kStudyTables[] = {"study", "sweep", "compare"};

struct Case {
  std::int64_t id = 0;
  std::string scenario;  // the case's scenario, TOML
  std::string base_dir;  // the directory its relative files are relative to (the scenario's)
  std::string vars;      // JSON object: varied key → value, in the spec's order
};

// The values of every case, numbered from 0: for each grid point (the last key fastest) every
// random sample, drawn from `seed` (std::mt19937_64; the same spec draws the same values).
// Each row holds the grid keys' values, then the random keys'.
std::vector<std::vector<Value>> draw_values(const Spec& spec);

// The scenario text with `values` applied to `keys` (toml++: parsed, set, written back; comments
// are lost) and the study tables removed. Throws io::InputError naming the key when the path
// cannot be set (an index past the array's end, a key below a value that is not a table).
std::string apply(const std::string& scenario_text, const std::string& label,
                  const std::vector<std::string>& keys, const std::vector<Value>& values);

// The label a case is read under: "<base_dir>/case N" (its relative files are found beside it,
// its messages name it).
std::string case_label(const std::string& base_dir, std::int64_t id);

// Every value of every varied key applied alone to the scenario, read by the scenario's reader
// (the one `lathectl run` uses): a key its system does not know or a value it refuses throws
// io::InputError at the spec's line of that key. Uniform draws are checked at both bounds,
// choices each, normal draws as drawn. A combination the reader refuses is the case's error row.
void check_values(const Spec& spec, const std::string& scenario_text,
                  const std::vector<std::vector<Value>>& values, const io::MaterialLibrary& lib);

// The spec's cases (draw_values, apply).
std::vector<Case> make_cases(const Spec& spec, const std::string& scenario_text,
                             const std::vector<std::vector<Value>>& values);

}  // namespace lathectl::sweep
