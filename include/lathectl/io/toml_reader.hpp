#pragma once
// Strict reading of TOML tables: typed getters with ranges and defaults, errors that name the
// file, the line and the full key, and a finish() that rejects every key nobody asked for.
// Used by every scenario and data-file parser; toml++ stays behind this interface.

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace toml {
inline namespace v3 {
class table;
class node;
}  // namespace v3
}  // namespace toml

namespace lathectl::io {

class KeyLocations;

// Accepted interval of a number; open ends exclude the bound.
struct Range {
  double lo = -1e300;
  double hi = 1e300;
  bool lo_open = false;
  bool hi_open = false;
  static constexpr Range positive() { return {0.0, 1e300, true, false}; }
  static constexpr Range non_negative() { return {0.0, 1e300, false, false}; }
  static constexpr Range closed(double a, double b) { return {a, b, false, false}; }
  static constexpr Range above(double a) { return {a, 1e300, true, false}; }  // (a, ∞)
  static constexpr Range any() { return {}; }
  [[nodiscard]] bool contains(double v) const noexcept;
  [[nodiscard]] std::string describe() const;
  [[nodiscard]] bool is_any() const noexcept { return lo <= -1e299 && hi >= 1e299; }
};

// One parameter, described once: its key (the file's unit is in the name: _mm, _MPa, _ms, ...),
// the range accepted in that unit, one line of meaning, and the factor from the file's unit to the
// settings struct's (SI, mostly). Its default is the settings struct's own initial value, so the
// C++ API, the scenario reader and the generated reference (docs/scenario-reference.md) cannot
// disagree: TableReader::read leaves the field as it is when the key is absent.
//
// Why this shape: a section reader stays a short, ordinary function (nested structs, derived
// defaults and cross-checks read as code), while every key it reads goes through one call that
// carries the whole description. Run in describe mode (TableReader::describing), the same function
// yields the reference tables; run on a file, it yields the effective settings a report shows.
//
// Three optional parts, for the keys that need them (designated initializers read best:
// {.key = "sensor_min", .range = ..., .doc = ..., .unit = "N or W"}):
//   unit:      when the name cannot carry it (a reading in the unit of the sensor chosen);
//   derived:   a default computed from other keys, as a formula ("feed_mm_per_rev"): the reference
//              shows it instead of a number the describe run made up, a run's settings show
//              "formula = value";
//   plausible: the values a shop would mean; a value inside `range` but outside it is read, and
//              a warning naming the key goes to stderr and into the report.
struct Param {
  std::string_view key;
  Range range = {};
  std::string_view doc = {};
  double scale = 1.0;  // value in the file × scale = value in the struct
  std::string_view unit = {};
  std::string_view derived = {};
  Range plausible = {};
};

// What a reader read (or, describing, would read): one row of the reference or of the effective
// settings. `value` and `fallback` are in the file's unit; `fallback` is empty for a required key.
struct ParamRecord {
  std::string key;    // full key, e.g. "controller.force_limit_N"
  std::string kind;   // "number", "integer", "boolean", "string", "one of ...", "table", ...
  std::string range;  // Range::describe() or the choices
  std::string fallback;
  bool required = false;
  std::string doc;
  std::string value;  // as read (empty when describing)
  std::string rules;  // cross-field rules (check()), for the reference
  std::string unit;   // the key's unit as a person writes it (Param::unit, else unit_of_key)
  std::string plausible;  // Param::plausible described, empty when any value in range is
};
using ParamLog = std::vector<ParamRecord>;

// The unit a key carries in its name, as a person writes it: "feed_mm_per_rev" → "mm/rev",
// "holder_stiffness_N_per_um" → "N/µm", "inertia_kg_m2" → "kg·m²", "damping_ratio" → "".
// "min" right after the quantity and before a unit is a minimum ("feed_min_mm_per_rev" → mm/rev);
// as the last token it is minutes ("tool_change_min").
std::string unit_of_key(std::string_view key);

// The known name nearest to `word` (a misspelling: a few letters added, dropped, changed or
// swapped, case ignored), or "" when none is near.
std::string nearest_name(std::string_view word, const std::vector<std::string>& known);

// A key the user wrote in another unit of the same quantity ("stiffness_N_per_um" for
// "stiffness_N_per_m"): `factor` turns the user's number into the known key's unit (1e6 here);
// nullopt when the names differ in more than the unit or the units measure different things.
struct UnitMismatch {
  std::string quantity;   // "stiffness"
  std::string user_unit;  // "N/µm"
  std::string unit;       // "N/m"
  double factor = 0.0;    // NaN when the units cannot be converted (mm/rev for mm/min)
};
std::optional<UnitMismatch> unit_mismatch(std::string_view user_key, std::string_view known_key);

// A parsed TOML document that owns its tree.
class TomlDocument {
 public:
  // Parse text; syntax errors become InputError "file:line:col: ...".
  static TomlDocument parse(std::string_view text, const std::string& file_label);
  static TomlDocument parse_file(const std::string& path);
  [[nodiscard]] const toml::table& root() const { return *root_; }
  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  std::shared_ptr<toml::table> root_;
  std::string file_;
};

class TableReader {
 public:
  // `locations`, when given, records where every key read (and every table) was written.
  TableReader(const toml::table& table, std::string file, std::string prefix,
              std::shared_ptr<KeyLocations> locations = nullptr);
  // A reader of no file that records every key it is asked for into `log` and answers with the
  // caller's default (or, for a required key, a value inside its range): running a section reader
  // on it lists that section's keys for the reference. check() never fails while describing.
  // `variant` 1 answers required keys with other in-range values: a default that changes with it
  // is derived from a required key and must say so (Param::derived; the reference test).
  static TableReader describing(std::string prefix, std::shared_ptr<ParamLog> log, int variant = 0);
  [[nodiscard]] bool is_describing() const { return table_ == nullptr; }
  // Every key read from now on is also recorded (value as written, or the default) into `log`.
  void record_into(std::shared_ptr<ParamLog> log) { log_ = std::move(log); }
  // Warnings (implausible values, "file:line:col: key 'k': ...") go into `sink`;
  // tables opened from this one share it.
  void warn_into(std::shared_ptr<std::vector<std::string>> sink) { warnings_ = std::move(sink); }
  // A warning located at `key` (a value read but not one a shop would mean). Describing: nothing.
  void warn(std::string_view key, const std::string& message) const;

  // The described way to read a key (see Param): absent → `field` keeps its value (the struct's
  // default); present → checked against p.range, times p.scale, stored.
  void read(const Param& p, double& field);
  void read(const Param& p, bool& field);
  void read(const Param& p, int& field);
  void read(const Param& p, std::size_t& field);
  // The same for a key without a default.
  void require(const Param& p, double& field);
  // An array of numbers, each in p.range, times p.scale; absent → empty (or, with min_count > 0,
  // required).
  std::vector<double> numbers(const Param& p, std::size_t min_count = 0);
  // A string that must be one of `choices`; absent → `fallback` (or required when none).
  std::string pick(const Param& p, const std::vector<std::string>& choices,
                   std::optional<std::string> fallback = std::nullopt);
  // A cross-field rule at `key`: fails with `message` unless `ok`; describing, it records the
  // rule beside the key instead (always: the reference lists every rule).
  void check(bool ok, std::string_view key, const std::string& message) const;
  // The one line of meaning of a key read with a plain getter (a table, an array of tables, a
  // string, pairs, ...): call it beside the read.
  void document(std::string_view key, std::string_view doc) const;

  [[nodiscard]] bool has(std::string_view key) const;
  double number(std::string_view key, Range range, std::optional<double> fallback = std::nullopt);
  std::int64_t integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                       std::optional<std::int64_t> fallback = std::nullopt);
  bool boolean(std::string_view key, std::optional<bool> fallback = std::nullopt);
  std::string string(std::string_view key, std::optional<std::string> fallback = std::nullopt);
  // A string that must be one of `choices`.
  std::string choice(std::string_view key, const std::vector<std::string>& choices,
                     std::optional<std::string> fallback = std::nullopt);
  std::vector<double> numbers(std::string_view key, Range range, std::size_t min_count = 0);
  // A non-empty array of strings, each one of `choices`.
  std::vector<std::string> choices(std::string_view key, const std::vector<std::string>& choices);
  std::optional<TableReader> table(std::string_view key, bool required = false);
  // Array of tables: [[key]] or key = [ {..}, {..} ].
  std::vector<TableReader> tables(std::string_view key);
  // Array of numeric pairs: key = [[a, b], ...].
  std::vector<std::pair<double, double>> pairs(std::string_view key, Range first, Range second);
  // Keys of this table (for data files keyed by name).
  [[nodiscard]] std::vector<std::string> keys() const;
  // Rejects keys that were never read. Call once everything was read.
  void finish() const;

  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] std::string full_key(std::string_view key) const;
  [[nodiscard]] int line() const;
  // InputError located at `key` (or at the table when the key is absent). When the key is
  // absent and the file writes an unread key that is a misspelling of it (or the same quantity
  // in another unit), the error is that key's, at its own line: the user's mistake, not its
  // consequence.
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;

 private:
  TableReader() = default;
  const toml::node* get(std::string_view key);
  double number_value(std::string_view key, Range range, std::optional<double> fallback);
  std::int64_t integer_value(std::string_view key, std::int64_t lo, std::int64_t hi,
                             std::optional<std::int64_t> fallback);
  bool boolean_value(std::string_view key, std::optional<bool> fallback);
  std::string string_value(std::string_view key, std::optional<std::string> fallback);
  std::string choice_value(std::string_view key, const std::vector<std::string>& choices,
                           std::optional<std::string> fallback);
  void log(std::string_view key, std::string kind, std::string range, std::string fallback,
           bool required, std::string_view doc, std::string value,
           std::string_view unit = {}) const;
  void check_plausible(const Param& p, double v) const;
  // Completes the row of a described key: its unit, plausible range and derived default.
  void describe_row(const Param& p, const std::string& value_default) const;
  // The error for the file's key `user` (unread) that stands for the reader's key `known`.
  [[noreturn]] void fail_unknown(std::string_view user, std::string_view known) const;
  const toml::table* table_ = nullptr;  // null when describing
  std::string file_;
  std::string prefix_;
  std::set<std::string, std::less<>> used_;
  std::shared_ptr<KeyLocations> locations_;
  std::shared_ptr<ParamLog> log_;
  std::shared_ptr<std::vector<std::string>> warnings_;
  int variant_ = 0;  // describing: which in-range value a required key gets
};

}  // namespace lathectl::io
