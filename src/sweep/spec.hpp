#pragma once
// The spec of `lathectl sweep` (docs/sweep.md): the scenario, the [grid] crossed with the
// [random] samples, and the [output] metrics. read_spec checks the spec's own form (every error
// names SPEC's file, line and key); whether the scenario's system knows a key and takes a value is
// checked by cases.hpp's check_values, with the scenario's own reader.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace lathectl::sweep {

// A value a case gives a key: a TOML integer, float, boolean or string.
using Value = std::variant<std::int64_t, double, bool, std::string>;

// Where the spec writes something (for errors).
struct Place {
  int line = 0;
  int column = 0;
};

// A key the sweep varies: "table.key" or "table.key[i]" (an array element by index), as in the
// scenario.
struct GridKey {
  std::string key;
  Place at;
  std::vector<Value> values;  // the grid's values, in the spec's order
  std::vector<Place> value_at;
};

struct Distribution {
  enum class Kind { Uniform, Normal, Choice };
  Kind kind = Kind::Uniform;
  double a = 0.0, b = 0.0;     // uniform: [lo, hi]; normal: mean, standard deviation
  std::vector<Value> choices;  // choice: drawn with equal probability
};

struct RandomKey {
  std::string key;
  Place at;
  Distribution dist;
};

// [report] (optional): the stability lobes' boundary of a machine file (`lathectl lobes`, system
// B) drawn over the heat maps of two grid keys, and the cases' verdict set against it.
struct LobesOverlay {
  std::filesystem::path machine;  // the machine file (relative ones made relative to SPEC)
  Place at;                       // the [report] table
  Place machine_at;
  std::string speed, depth;       // the grid keys on the lobes' speed axis and depth axis
  Place speed_at, depth_at;
  // The lobes' limit depth b [mm] read as the depth key's value y: y = b without an exponent,
  // y = reference·(b/reference)^(1/(1 − exponent)) with one (a force ∝ y^(1 − exponent) whose
  // coefficient the machine file gives at y = reference).
  double depth_reference = 0.0;   // 0: none
  double depth_exponent = 0.0;
  std::string chatter;            // the metric whose value above chatter_above means chatter
  double chatter_above = 1.0;
};

struct Spec {
  std::string file;                   // the spec's path as given (messages)
  std::filesystem::path scenario;     // the scenario file (relative ones made relative to SPEC)
  Place scenario_at;                  // where the spec names it
  std::vector<GridKey> grid;          // in the spec's order (the last varies fastest)
  std::size_t samples = 0;            // [random] samples (0: no [random])
  std::uint64_t seed = 0;             // [random] seed
  Place random_at;                    // the [random] table
  std::vector<RandomKey> random;      // in the spec's order
  std::vector<std::string> metrics;   // [output] metrics ("a.b"); empty: every numeric scalar
  std::optional<LobesOverlay> lobes;  // [report]
  // The varied keys: grid keys then random keys (the columns of cases.csv and results.csv).
  [[nodiscard]] std::vector<std::string> varied_keys() const;
  // The place of a varied key (its line in [grid] or [random]).
  [[nodiscard]] Place place_of(const std::string& key) const;
};

// The scenario's text; a file that cannot be read is an error at the spec's `scenario` line.
std::string read_scenario(const Spec& spec);

// Reads SPEC; throws io::InputError "SPEC:line:col: ..." naming the key.
Spec read_spec(const std::string& path);
Spec parse_spec(std::string_view text, const std::string& file_label);

// A key's path: "cut.depth_mm[0]" → {{"cut", -1}, {"depth_mm", 0}}; empty when malformed.
struct PathPart {
  std::string name;
  long index = -1;  // -1: none
};
std::vector<PathPart> parse_key_path(const std::string& key);

// A number's value as a double; NaN for a boolean or a string.
double number_of(const Value& v);

// Value as TOML/JSON writes it (a string quoted as JSON does).
std::string to_text(const Value& v);

}  // namespace lathectl::sweep
