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
  static Range positive() { return {0.0, 1e300, true, false}; }
  static Range non_negative() { return {0.0, 1e300, false, false}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range any() { return {}; }
  [[nodiscard]] bool contains(double v) const noexcept;
  [[nodiscard]] std::string describe() const;
};

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
  // InputError located at `key` (or at the table when the key is absent).
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;

 private:
  const toml::node* get(std::string_view key);
  const toml::table* table_;
  std::string file_;
  std::string prefix_;
  std::set<std::string, std::less<>> used_;
  std::shared_ptr<KeyLocations> locations_;
};

}  // namespace lathectl::io
