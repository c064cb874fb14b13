// TableReader's reads by Param (the key, its range, description and scale in one place): the
// value read, its row in the reference and a run's settings, the plausibility warning.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lathectl/io/toml_reader.hpp"
#include "toml_reader_text.hpp"

namespace lathectl::io {

using detail::fmt_num;
using detail::quoted_list;

void TableReader::log(std::string_view key, std::string kind, std::string range,
                      std::string fallback, bool required, std::string_view doc, std::string value,
                      std::string_view unit) const {
  if (!log_) return;
  const std::string k = full_key(key);
  for (auto& r : *log_)
    if (r.key == k) {  // read twice, or documented after reading: complete the first row
      if (r.doc.empty()) r.doc = doc;
      if (r.kind.empty()) r.kind = std::move(kind);
      if (!unit.empty()) r.unit = unit;
      return;
    }
  log_->push_back({k,
                   std::move(kind),
                   std::move(range),
                   std::move(fallback),
                   required,
                   std::string(doc),
                   std::move(value),
                   {},
                   unit.empty() ? unit_of_key(key) : std::string(unit),
                   {}});
}

// Inside the valid range but outside what a shop would mean: read, and warned about.
void TableReader::check_plausible(const Param& p, double v) const {
  if (is_describing() || p.plausible.is_any() || p.plausible.contains(v)) return;
  const std::string unit = p.unit.empty() ? unit_of_key(p.key) : std::string(p.unit);
  warn(p.key, fmt_num(v) + (unit.empty() ? "" : " " + unit) +
                  " is not a value a shop would mean (usually " + p.plausible.describe() +
                  (unit.empty() ? "" : " " + unit) + "); check the number and its unit");
}

// A row's plausible range for the reference.
namespace {
std::string plausible_text(const Param& p) {
  return p.plausible.is_any() ? std::string() : p.plausible.describe();
}
}  // namespace

void TableReader::check(bool ok, std::string_view key, const std::string& message) const {
  if (is_describing()) {  // every rule goes into the reference, whatever the neutral values say
    if (log_)
      for (auto& r : *log_)
        if (r.key == full_key(key)) {
          r.rules += (r.rules.empty() ? "" : "; ") + message;
          return;
        }
    return;
  }
  if (!ok) fail(key, message);
}

void TableReader::read(const Param& p, double& field) {
  const double shop = field / p.scale;
  const double v = number(p.key, p.range, shop);
  log(p.key, "number", p.range.describe(), fmt_num(shop), false, p.doc, fmt_num(v));
  describe_row(p, fmt_num(shop));
  if (has(p.key)) {
    check_plausible(p, v);
    field = v * p.scale;  // absent: the default's exact bits, not ÷ and × scale
  }
}

void TableReader::require(const Param& p, double& field) {
  const double v = number(p.key, p.range);
  log(p.key, "number", p.range.describe(), "", true, p.doc, fmt_num(v));
  describe_row(p, "");
  check_plausible(p, v);
  field = v * p.scale;
}

void TableReader::describe_row(const Param& p, const std::string& value_default) const {
  if (!log_) return;
  for (auto& r : *log_) {
    if (r.key != full_key(p.key)) continue;
    if (!p.unit.empty()) r.unit = p.unit;
    r.plausible = plausible_text(p);
    // A derived default is its formula in the reference, "formula = value" in a run's settings.
    if (!p.derived.empty())
      r.fallback =
          is_describing() ? std::string(p.derived) : std::string(p.derived) + " = " + value_default;
    return;
  }
}

std::vector<double> TableReader::numbers(const Param& p, std::size_t min_count) {
  std::vector<double> v = numbers(p.key, p.range, min_count);
  std::string shown;
  for (double x : v) shown += (shown.empty() ? "" : ", ") + fmt_num(x);
  log(p.key, "array of numbers", p.range.describe(), min_count ? "" : "[]", min_count > 0, p.doc,
      "[" + shown + "]");
  describe_row(p, "");
  for (double x : v) check_plausible(p, x);
  if (p.scale != 1.0)
    for (double& x : v) x *= p.scale;
  return v;
}

void TableReader::read(const Param& p, bool& field) {
  const bool v = boolean(p.key, field);
  log(p.key, "boolean", "true or false", field ? "true" : "false", false, p.doc,
      v ? "true" : "false");
  describe_row(p, field ? "true" : "false");
  field = v;
}

void TableReader::read(const Param& p, int& field) {
  const auto lo = static_cast<std::int64_t>(std::ceil(std::max(p.range.lo, -2147483648.0)));
  const auto hi = static_cast<std::int64_t>(std::floor(std::min(p.range.hi, 2147483647.0)));
  const auto v = integer(p.key, lo, hi, field);
  log(p.key, "integer", p.range.describe(), std::to_string(field), false, p.doc,
      std::to_string(v));
  describe_row(p, std::to_string(field));
  if (has(p.key)) check_plausible(p, static_cast<double>(v));
  field = static_cast<int>(v);
}

void TableReader::read(const Param& p, std::size_t& field) {
  const auto lo = static_cast<std::int64_t>(std::ceil(std::max(p.range.lo, 0.0)));
  const auto hi = static_cast<std::int64_t>(std::floor(std::min(p.range.hi, 9.2e18)));
  const auto v = integer(p.key, lo, hi, static_cast<std::int64_t>(field));
  log(p.key, "integer", p.range.describe(), std::to_string(field), false, p.doc,
      std::to_string(v));
  describe_row(p, std::to_string(field));
  if (has(p.key)) check_plausible(p, static_cast<double>(v));
  field = static_cast<std::size_t>(v);
}

std::string TableReader::pick(const Param& p, const std::vector<std::string>& choices,
                              std::optional<std::string> fallback) {
  std::string v = choice(p.key, choices, fallback);
  log(p.key, "string", "one of " + quoted_list(choices), fallback ? "\"" + *fallback + "\"" : "",
      !fallback, p.doc, v);
  return v;
}

}  // namespace lathectl::io
