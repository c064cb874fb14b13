#pragma once
// A scenario's acceptance criteria: what the user's part must achieve, in the user's terms (a
// Cpk, a profile error in µm, a force over its limit in %), as opposed to the model checks (the
// seeds' claims: does the model reproduce what the document says?). Each system offers its keys
// for an optional [acceptance] table, each described once (key with its unit, range, meaning,
// default limit), so the reference, `check` and the report's settings list them like any other
// key. `lathectl run --strict` is decided by these (with alarms and unfinished parts), never by
// the model checks. The judging, against a run's numbers, is io::Acceptance (verdict.hpp).

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {

// One criterion a system offers. The key starts with its direction (`max_`: value ≤ limit;
// `min_`: value ≥ limit, as [spindle] min_rpm, max_rpm) and ends with the unit of value and limit
// (`_um`, `_pct`, `_s`; none for a ratio such as Cpk: a trailing `_min` would read as minutes).
struct CriterionKey {
  std::string_view key;    // "min_cpk"
  std::string_view label;  // the report's name of the value judged: "Cpk of the finished sizes"
  bool at_least = false;   // value ≥ limit (min_…); otherwise value ≤ limit (max_…)
  // The system's default limit. 0: not judged unless the scenario gives one (every such key's
  // doc says so); NaN: derived from other settings by the system's reader ("derived").
  double fallback = 0.0;
  Range range = Range::non_negative();
  std::string_view doc = {};
};

// The limits a scenario judges its run by: the system's keys, each with the limit the scenario's
// [acceptance] gave or the default.
class AcceptanceLimits {
 public:
  AcceptanceLimits() = default;
  explicit AcceptanceLimits(std::span<const CriterionKey> keys);
  [[nodiscard]] std::span<const CriterionKey> keys() const { return keys_; }
  // The limit of `key` (NaN: unknown key); 0 for a criterion not judged.
  [[nodiscard]] double limit(std::string_view key) const;
  // Whether the scenario wrote the key (the report says "yours" or "default").
  [[nodiscard]] bool stated(std::string_view key) const;
  // A derived default, set by the system's reader before read_acceptance (as D's backstop).
  void set_default(std::string_view key, double limit);

 private:
  friend void read_acceptance(TableReader& root, AcceptanceLimits& limits);
  [[nodiscard]] std::size_t index(std::string_view key) const;
  std::span<const CriterionKey> keys_;
  std::vector<double> limits_;
  std::vector<char> stated_;
};

// Reads the optional [acceptance] table of `root` with the keys `limits` was made with; absent
// keys keep their defaults. Describing, it lists every key for the reference.
void read_acceptance(TableReader& root, AcceptanceLimits& limits);

}  // namespace lathectl::io
