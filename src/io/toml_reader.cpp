#include "lathectl/io/toml_reader.hpp"

#include "lathectl/io/input_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {

namespace {
std::string fmt_num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date/time";
  }
}
// A value inside `r` for a required key while describing (the reference never shows it);
// variant 1 another one, to find the defaults that follow a required key.
double neutral(const Range& r, int variant = 0) {
  const bool has_lo = r.lo > -1e299, has_hi = r.hi < 1e299;
  if (variant == 1) {
    if (has_lo && has_hi) return r.lo + 0.25 * (r.hi - r.lo);
    if (has_lo) return r.lo + 3.0;
    if (has_hi) return r.hi - 3.0;
    return 1.0;
  }
  if (has_lo && has_hi) return r.lo_open || r.hi_open ? 0.5 * (r.lo + r.hi) : r.lo;
  if (has_lo) return r.lo_open ? r.lo + 1.0 : r.lo;
  if (has_hi) return r.hi_open ? r.hi - 1.0 : r.hi;
  return 0.0;
}
// A number as TOML takes it and a person reads it: 6.0e6, 0.25, 1500.0.
std::string toml_number(double v) {
  char buf[64];
  const double a = std::abs(v);
  if (a == 0.0 || (a >= 1e-3 && a < 1e6)) {
    std::snprintf(buf, sizeof buf, "%.6g", v);
    std::string s = buf;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return s;
  }
  const int e = static_cast<int>(std::floor(std::log10(a)));
  std::snprintf(buf, sizeof buf, "%.6g", v / std::pow(10.0, e));
  std::string m = buf;
  if (m.find('.') == std::string::npos) m += ".0";
  return m + "e" + std::to_string(e);
}
std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}
// Optimal string alignment distance: insertions, deletions, substitutions and swaps of two
// neighbours, one edit each.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

// The units a key's name may end in: how a person writes each, and its size in base units
// (m, kg, s, revolutions, A, K) with the exponents of those.
struct UnitToken {
  std::string_view in, out;
  double factor;           // in base units; 0: not convertible (dB)
  std::array<int, 6> dim;  // m, kg, s, rev, A, K
};
constexpr double kPi = 3.14159265358979323846;
constexpr UnitToken kUnits[] = {
    {"mm", "mm", 1e-3, {1, 0, 0, 0, 0, 0}},
    {"um", "µm", 1e-6, {1, 0, 0, 0, 0, 0}},
    {"m", "m", 1.0, {1, 0, 0, 0, 0, 0}},
    {"km", "km", 1e3, {1, 0, 0, 0, 0, 0}},
    {"m2", "m²", 1.0, {2, 0, 0, 0, 0, 0}},
    {"m3", "m³", 1.0, {3, 0, 0, 0, 0, 0}},
    {"cm2", "cm²", 1e-4, {2, 0, 0, 0, 0, 0}},
    {"cm3", "cm³", 1e-6, {3, 0, 0, 0, 0, 0}},
    {"mm2", "mm²", 1e-6, {2, 0, 0, 0, 0, 0}},
    {"mm3", "mm³", 1e-9, {3, 0, 0, 0, 0, 0}},
    {"L", "L", 1e-3, {3, 0, 0, 0, 0, 0}},
    {"s", "s", 1.0, {0, 0, 1, 0, 0, 0}},
    {"ms", "ms", 1e-3, {0, 0, 1, 0, 0, 0}},
    {"us", "µs", 1e-6, {0, 0, 1, 0, 0, 0}},
    {"min", "min", 60.0, {0, 0, 1, 0, 0, 0}},
    {"Hz", "Hz", 1.0, {0, 0, -1, 1, 0, 0}},
    {"kHz", "kHz", 1e3, {0, 0, -1, 1, 0, 0}},
    {"rpm", "rpm", 1.0 / 60, {0, 0, -1, 1, 0, 0}},
    {"rpm2", "rpm²", 1.0 / 3600, {0, 0, -2, 2, 0, 0}},
    {"rev", "rev", 1.0, {0, 0, 0, 1, 0, 0}},
    {"rad", "rad", 0.5 / kPi, {0, 0, 0, 1, 0, 0}},
    {"deg", "°", 1.0 / 360, {0, 0, 0, 1, 0, 0}},
    {"N", "N", 1.0, {1, 1, -2, 0, 0, 0}},
    {"kN", "kN", 1e3, {1, 1, -2, 0, 0, 0}},
    {"Nm", "N·m", 1.0, {2, 1, -2, 0, 0, 0}},
    {"J", "J", 1.0, {2, 1, -2, 0, 0, 0}},
    {"W", "W", 1.0, {2, 1, -3, 0, 0, 0}},
    {"kW", "kW", 1e3, {2, 1, -3, 0, 0, 0}},
    {"Pa", "Pa", 1.0, {-1, 1, -2, 0, 0, 0}},
    {"MPa", "MPa", 1e6, {-1, 1, -2, 0, 0, 0}},
    {"GPa", "GPa", 1e9, {-1, 1, -2, 0, 0, 0}},
    {"bar", "bar", 1e5, {-1, 1, -2, 0, 0, 0}},
    {"kg", "kg", 1.0, {0, 1, 0, 0, 0, 0}},
    {"g", "g", 1e-3, {0, 1, 0, 0, 0, 0}},
    {"A", "A", 1.0, {0, 0, 0, 0, 1, 0}},
    {"V", "V", 1.0, {2, 1, -3, 0, -1, 0}},
    {"mV", "mV", 1e-3, {2, 1, -3, 0, -1, 0}},
    {"ohm", "Ω", 1.0, {2, 1, -3, 0, -2, 0}},
    {"H", "H", 1.0, {2, 1, -2, 0, -2, 0}},
    {"Wb", "Wb", 1.0, {2, 1, -2, 0, -1, 0}},
    {"Wb2", "Wb²", 1.0, {4, 2, -4, 0, -2, 0}},
    {"K", "K", 1.0, {0, 0, 0, 0, 0, 1}},
    {"percent", "%", 0.01, {0, 0, 0, 0, 0, 0}},
    {"pct", "%", 0.01, {0, 0, 0, 0, 0, 0}},
    {"dB", "dB", 0.0, {0, 0, 0, 0, 0, 0}},
};
const UnitToken* unit_token(std::string_view t) {
  for (const auto& u : kUnits)
    if (u.in == t) return &u;
  return nullptr;
}

// A key split into its quantity and its unit: "feed_min_mm_per_rev" → {"feed_min", [mm, per,
// rev]}. The unit is the tokens after the first '_' from which every token is a unit, "per"
// between units; "min" (and "max") directly after the quantity and before another unit is a
// minimum, not minutes. No unit: {key, {}}.
struct SplitKey {
  std::string_view quantity;
  std::vector<std::string_view> unit;  // tokens, "per" included
};
SplitKey split_key(std::string_view key) {
  for (std::size_t i = key.find('_'); i != std::string_view::npos; i = key.find('_', i + 1)) {
    if (i < 2) continue;  // "n_s" is a count, not seconds
    std::vector<std::string_view> tokens;
    bool all = true;
    for (std::size_t a = i + 1; a <= key.size();) {
      std::size_t b = key.find('_', a);
      if (b == std::string_view::npos) b = key.size();
      const auto t = key.substr(a, b - a);
      if (t != "per" && !unit_token(t)) {
        all = false;
        break;
      }
      tokens.push_back(t);
      a = b + 1;
    }
    if (!all || tokens.empty() || tokens.back() == "per") continue;
    if (tokens.size() > 1 && tokens.front() == "min" && tokens[1] != "per") continue;
    return {key.substr(0, i), std::move(tokens)};
  }
  return {key, {}};
}
std::string render_unit(const std::vector<std::string_view>& tokens) {
  std::string out;
  bool after_per = true;
  for (const auto t : tokens) {
    if (t == "per") {
      out += out.empty() ? "1/" : "/";
      after_per = true;
    } else {
      out += (after_per ? "" : "·") + std::string(unit_token(t)->out);
      after_per = false;
    }
  }
  return out;
}
// The unit's size in base units and its dimension; factor 0 when it cannot be converted.
std::pair<double, std::array<int, 6>> unit_size(const std::vector<std::string_view>& tokens) {
  double f = 1.0;
  std::array<int, 6> dim{};
  int sign = 1;
  for (const auto t : tokens) {
    if (t == "per") {
      sign = -1;
      continue;
    }
    const auto* u = unit_token(t);
    f = sign > 0 ? f * u->factor : f / u->factor;
    if (u->factor == 0.0) return {0.0, dim};
    for (std::size_t k = 0; k < dim.size(); ++k) dim[k] += sign * u->dim[k];
  }
  return {f, dim};
}
std::string quoted_list(const std::vector<std::string>& choices) {
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  return list;
}
}  // namespace

bool Range::contains(double v) const noexcept {
  if (!std::isfinite(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_lo = lo > -1e299;
  const bool has_hi = hi < 1e299;
  if (has_lo && has_hi)
    return std::string(lo_open ? "(" : "[") + fmt_num(lo) + ", " + fmt_num(hi) +
           (hi_open ? ")" : "]");
  if (has_lo) return std::string(lo_open ? "> " : "≥ ") + fmt_num(lo);
  if (has_hi) return std::string(hi_open ? "< " : "≤ ") + fmt_num(hi);
  return "finite";
}

std::string unit_of_key(std::string_view key) {
  const SplitKey k = split_key(key);
  return k.unit.empty() ? "" : render_unit(k.unit);
}

std::string nearest_name(std::string_view word, const std::vector<std::string>& known) {
  const std::string w = lower(word);
  // A few edits, fewer for short names: "tol" must not become "too".
  const std::size_t allowed = w.size() <= 4 ? 1 : w.size() <= 8 ? 2 : 3;
  std::string best;
  std::size_t best_d = allowed + 1;
  for (const auto& k : known) {
    // At least |Δlength| edits: skip the far ones before the quadratic table (fuzzed input).
    const std::size_t gap = k.size() > w.size() ? k.size() - w.size() : w.size() - k.size();
    if (k == word || gap > allowed) continue;
    const std::size_t d = edit_distance(w, lower(k));
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  return best;
}

std::optional<UnitMismatch> unit_mismatch(std::string_view user_key, std::string_view known_key) {
  const SplitKey u = split_key(user_key), k = split_key(known_key);
  if (k.unit.empty() || lower(u.quantity) != lower(k.quantity) || user_key == known_key)
    return std::nullopt;
  UnitMismatch m;
  m.quantity = std::string(k.quantity);
  std::replace(m.quantity.begin(), m.quantity.end(), '_', ' ');
  m.unit = render_unit(k.unit);
  m.factor = std::nan("");
  if (u.unit.empty()) return m;  // "stiffness = 6e6": no unit written
  m.user_unit = render_unit(u.unit);
  const auto [fu, du] = unit_size(u.unit);
  const auto [fk, dk] = unit_size(k.unit);
  if (fu != 0.0 && fk != 0.0 && du == dk) m.factor = fu / fk;
  return m;
}

TomlDocument TomlDocument::parse(std::string_view text, const std::string& file_label) {
  TomlDocument d;
  d.file_ = file_label;
  try {
    d.root_ = std::make_shared<toml::table>(toml::parse(text, file_label));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(located(file_label, static_cast<int>(b.line), static_cast<int>(b.column),
                             "TOML syntax error: " + std::string(e.description())));
  }
  return d;
}

TomlDocument TomlDocument::parse_file(const std::string& path) {
  return parse(read_input_file(path, "a TOML file", kMaxTomlBytes), path);
}

TableReader::TableReader(const toml::table& table, std::string file, std::string prefix,
                         std::shared_ptr<KeyLocations> locations)
    : table_(&table),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      locations_(std::move(locations)) {}

TableReader TableReader::describing(std::string prefix, std::shared_ptr<ParamLog> log,
                                    int variant) {
  TableReader r;
  r.file_ = "(reference)";
  r.prefix_ = std::move(prefix);
  r.log_ = std::move(log);
  r.variant_ = variant;
  return r;
}

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

void TableReader::warn(std::string_view key, const std::string& message) const {
  if (is_describing() || !warnings_) return;
  const toml::node* n = table_->get(key);
  const auto& src = n ? n->source().begin : table_->source().begin;
  warnings_->push_back(located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
                               "key '" + full_key(key) + "': " + message));
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

std::string TableReader::full_key(std::string_view key) const {
  return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
}

int TableReader::line() const {
  if (is_describing()) return 0;
  return static_cast<int>(table_->source().begin.line);
}

void TableReader::fail(std::string_view key, const std::string& message) const {
  if (is_describing())  // a reader that fails on defaults: use check() for cross-field rules
    throw InputError("describing '" + full_key(key) + "': " + message);
  if (!table_->contains(key)) {
    // Absent: is it there under a misspelt name, or in another unit? That is the mistake.
    std::vector<std::string> unread;
    for (const auto& [k, v] : *table_)
      if (used_.find(k.str()) == used_.end()) unread.emplace_back(k.str());
    for (const auto& u : unread)
      if (unit_mismatch(u, key)) fail_unknown(u, key);
    const std::string near = nearest_name(key, unread);
    if (!near.empty()) fail_unknown(near, key);
  }
  const toml::node* n = table_->get(key);
  const auto& src = n ? n->source().begin : table_->source().begin;
  throw InputError(located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
                           "key '" + full_key(key) + "': " + message));
}

bool TableReader::has(std::string_view key) const {
  if (is_describing()) return false;
  return table_->contains(key);
}

const toml::node* TableReader::get(std::string_view key) {
  used_.emplace(key);
  if (is_describing()) return nullptr;
  const toml::node* n = table_->get(key);
  if (n && locations_) {
    const auto& src = n->source().begin;
    locations_->record(full_key(key), static_cast<int>(src.line), static_cast<int>(src.column));
  }
  return n;
}

double TableReader::number_value(std::string_view key, Range range, std::optional<double> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) {
      log(key, "number", range.describe(), "", true, "", "");
      return neutral(range, variant_);
    }
    fail(key, "missing; expected a number " + range.describe());
  }
  double v = 0.0;
  if (auto f = n->as_floating_point())
    v = f->get();
  else if (auto i = n->as_integer())
    v = static_cast<double>(i->get());
  else
    fail(key, "expected a number " + range.describe() + ", got " + type_name(*n));
  if (!range.contains(v))
    fail(key, "expected a number " + range.describe() + ", got " + fmt_num(v));
  return v;
}

std::int64_t TableReader::integer_value(std::string_view key, std::int64_t lo, std::int64_t hi,
                                  std::optional<std::int64_t> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) {
      log(key, "integer", "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]", "", true, "",
          "");
      return variant_ == 1 && lo < hi ? lo + 1 : lo;
    }
    fail(key, "missing; expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "]");
  }
  auto i = n->as_integer();
  if (!i) fail(key, "expected an integer, got " + type_name(*n));
  const std::int64_t v = i->get();
  if (v < lo || v > hi)
    fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "], got " + std::to_string(v));
  return v;
}

bool TableReader::boolean_value(std::string_view key, std::optional<bool> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) return false;
    fail(key, "missing; expected true or false");
  }
  auto b = n->as_boolean();
  if (!b) fail(key, "expected true or false, got " + type_name(*n));
  return b->get();
}

std::string TableReader::string_value(std::string_view key, std::optional<std::string> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) {
      log(key, "string", "", "", true, "", "");
      return "";
    }
    fail(key, "missing; expected a string");
  }
  auto s = n->as_string();
  if (!s) fail(key, "expected a string, got " + type_name(*n));
  return s->get();
}

std::string TableReader::choice_value(std::string_view key, const std::vector<std::string>& choices,
                                std::optional<std::string> fallback) {
  const std::string list = quoted_list(choices);
  if (is_describing()) {
    used_.emplace(key);
    log(key, "string", "one of " + list, fallback ? "\"" + *fallback + "\"" : "", !fallback, "", "");
    return fallback ? *fallback : choices.front();
  }
  if (!has(key) && !fallback) {
    used_.emplace(key);
    fail(key, "missing; expected one of " + list);
  }
  if (!has(key) && fallback) {  // an optional choice may default to "" (none)
    used_.emplace(key);
    return *fallback;
  }
  const std::string v = string_value(key, fallback);
  for (const auto& c : choices)
    if (c == v) return v;
  const std::string near = nearest_name(v, choices);
  fail(key, "expected one of " + list + ", got \"" + v + "\"" +
                (near.empty() ? "" : " — did you mean \"" + near + "\"?"));
}

// The public getters: the value, and a row of the log (in both modes).
double TableReader::number(std::string_view key, Range range, std::optional<double> fallback) {
  const double v = number_value(key, range, fallback);
  // A NaN default is one the section reader derives from other keys (its description says how).
  const std::string shown_default =
      !fallback ? "" : std::isnan(*fallback) ? "derived" : fmt_num(*fallback);
  log(key, "number", range.describe(), shown_default, !fallback, "",
      is_describing() ? "" : fmt_num(v));
  return v;
}

std::int64_t TableReader::integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                                  std::optional<std::int64_t> fallback) {
  const std::int64_t v = integer_value(key, lo, hi, fallback);
  log(key, "integer", "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
      fallback ? std::to_string(*fallback) : "", !fallback, "",
      is_describing() ? "" : std::to_string(v));
  return v;
}

bool TableReader::boolean(std::string_view key, std::optional<bool> fallback) {
  const bool v = boolean_value(key, fallback);
  log(key, "boolean", "true or false", fallback ? (*fallback ? "true" : "false") : "", !fallback,
      "", is_describing() ? "" : (v ? "true" : "false"));
  return v;
}

std::string TableReader::string(std::string_view key, std::optional<std::string> fallback) {
  std::string v = string_value(key, fallback);
  log(key, "string", "", fallback ? "\"" + *fallback + "\"" : "", !fallback, "",
      is_describing() ? "" : v);
  return v;
}

std::string TableReader::choice(std::string_view key, const std::vector<std::string>& choices,
                                std::optional<std::string> fallback) {
  std::string v = choice_value(key, choices, fallback);
  log(key, "string", "one of " + quoted_list(choices), fallback ? "\"" + *fallback + "\"" : "",
      !fallback, "", is_describing() ? "" : v);
  return v;
}

void TableReader::document(std::string_view key, std::string_view doc) const {
  log(key, "", "", "", false, doc, "");
}

std::vector<double> TableReader::numbers(std::string_view key, Range range, std::size_t min_count) {
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "array of numbers", range.describe(), min_count ? "" : "[]", min_count > 0, "", "");
    return std::vector<double>(min_count, neutral(range, variant_));
  }
  if (!n) {
    if (min_count == 0) return {};
    fail(key, "missing; expected an array of numbers");
  }
  auto a = n->as_array();
  if (!a) fail(key, "expected an array of numbers, got " + type_name(*n));
  std::vector<double> out;
  for (const auto& e : *a) {
    double v = 0.0;
    if (auto f = e.as_floating_point())
      v = f->get();
    else if (auto i = e.as_integer())
      v = static_cast<double>(i->get());
    else
      fail(key, "expected an array of numbers, found " + type_name(e));
    if (!range.contains(v))
      fail(key, "array element " + fmt_num(v) + " outside " + range.describe());
    out.push_back(v);
  }
  if (out.size() < min_count)
    fail(key, "expected at least " + std::to_string(min_count) + " numbers");
  return out;
}

std::vector<std::string> TableReader::choices(std::string_view key,
                                              const std::vector<std::string>& allowed) {
  const std::string list = quoted_list(allowed);
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "array of strings", "each one of " + list, "", true, "", "");
    return {allowed.front()};
  }
  if (!n) fail(key, "missing; expected an array of " + list);
  auto a = n->as_array();
  if (!a || a->empty()) fail(key, "expected a non-empty array of " + list);
  std::vector<std::string> out;
  for (const auto& e : *a) {
    auto str = e.as_string();
    if (!str) fail(key, "expected strings, one of " + list);
    const std::string v = str->get();
    if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
      const std::string near = nearest_name(v, allowed);
      fail(key, "expected each of " + list + ", got \"" + v + "\"" +
                    (near.empty() ? "" : " — did you mean \"" + near + "\"?"));
    }
    out.push_back(v);
  }
  std::string shown;
  for (const auto& v : out) shown += (shown.empty() ? "" : ", ") + v;
  log(key, "array of strings", "each one of " + list, "", true, "", "[" + shown + "]");
  return out;
}

std::optional<TableReader> TableReader::table(std::string_view key, bool required) {
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "table", "", required ? "" : "absent", required, "", "");
    return describing(full_key(key), log_, variant_);
  }
  // A heading in the run's settings, as in the reference (the settings table leaves it out).
  log(key, "table", "", required ? "" : "absent", required, "", "");
  if (!n) {
    if (required) fail(key, "missing table");
    return std::nullopt;
  }
  auto t = n->as_table();
  if (!t) fail(key, "expected a table, got " + type_name(*n));
  TableReader child(*t, file_, full_key(key), locations_);
  child.log_ = log_;
  child.warnings_ = warnings_;
  return child;
}

std::vector<TableReader> TableReader::tables(std::string_view key) {
  const toml::node* n = get(key);
  std::vector<TableReader> out;
  if (is_describing()) {
    log(key, "array of tables", "", "none", false, "", "");
    out.push_back(describing(full_key(key) + "[]", log_, variant_));
    return out;
  }
  log(key, "array of tables", "", "none", false, "", "");
  if (!n) return out;
  auto a = n->as_array();
  if (!a) fail(key, "expected an array of tables, got " + type_name(*n));
  std::size_t i = 0;
  for (const auto& e : *a) {
    auto t = e.as_table();
    if (!t) fail(key, "expected an array of tables, found " + type_name(e));
    const std::string name = full_key(key) + "[" + std::to_string(i++) + "]";
    if (locations_) {
      const auto& src = t->source().begin;
      locations_->record(name, static_cast<int>(src.line), static_cast<int>(src.column));
    }
    out.emplace_back(*t, file_, name, locations_);
    out.back().log_ = log_;
    out.back().warnings_ = warnings_;
  }
  return out;
}

std::vector<std::pair<double, double>> TableReader::pairs(std::string_view key, Range first,
                                                          Range second) {
  const toml::node* n = get(key);
  std::vector<std::pair<double, double>> out;
  if (is_describing()) log(key, "array of [a, b]", first.describe() + " × " + second.describe(), "[]", false, "", "");
  if (!n) return out;
  auto a = n->as_array();
  if (!a) fail(key, "expected an array of [a, b] pairs, got " + type_name(*n));
  for (const auto& e : *a) {
    auto p = e.as_array();
    if (!p || p->size() != 2) fail(key, "expected an array of [a, b] pairs");
    double v[2] = {0, 0};
    for (std::size_t k = 0; k < 2; ++k) {
      const auto& x = *p->get(k);
      if (auto f = x.as_floating_point())
        v[k] = f->get();
      else if (auto i = x.as_integer())
        v[k] = static_cast<double>(i->get());
      else
        fail(key, "expected numbers in the pairs");
    }
    if (!first.contains(v[0]) || !second.contains(v[1]))
      fail(key, "pair [" + fmt_num(v[0]) + ", " + fmt_num(v[1]) + "] outside " + first.describe() +
                    " × " + second.describe());
    out.emplace_back(v[0], v[1]);
  }
  return out;
}

std::vector<std::string> TableReader::keys() const {
  std::vector<std::string> out;
  if (is_describing()) return out;
  for (const auto& [k, v] : *table_) out.emplace_back(k.str());
  return out;
}

void TableReader::fail_unknown(std::string_view user, std::string_view known) const {
  const toml::node* n = table_->get(user);
  const auto& src = n->source().begin;
  const bool is_table = n->is_table() || (n->is_array_of_tables() && !n->as_array()->empty());
  std::string msg =
      std::string(is_table ? "unknown table '" : "unknown key '") + full_key(user) + "'";
  if (const auto m = unit_mismatch(user, known)) {
    // "stiffness is given in N/m: stiffness_N_per_m = 6.0e6 for 6 N/µm"
    msg += ": " + m->quantity + " is given in " + m->unit + ": " + std::string(known);
    double v = std::nan("");
    if (auto f = n->as_floating_point())
      v = f->get();
    else if (auto i = n->as_integer())
      v = static_cast<double>(i->get());
    if (std::isfinite(v) && std::isfinite(m->factor))
      msg += " = " + toml_number(v * m->factor) + " for " + fmt_num(v) + " " + m->user_unit;
    else if (!m->user_unit.empty())
      msg += " (" + m->user_unit + " is not a unit of it)";
  } else {
    msg += " — did you mean '" + full_key(known) + "'?";  // the full key, as every message
  }
  throw InputError(located(file_, static_cast<int>(src.line), static_cast<int>(src.column), msg));
}

void TableReader::finish() const {
  if (is_describing()) return;
  // The first unknown key as the file reads (the table iterates by name).
  const toml::node* first = nullptr;
  std::string first_key;
  for (const auto& [k, v] : *table_) {
    if (used_.find(k.str()) != used_.end()) continue;
    const auto& a = v.source().begin;
    if (!first || a.line < first->source().begin.line ||
        (a.line == first->source().begin.line && a.column < first->source().begin.column)) {
      first = &v;
      first_key = k.str();
    }
  }
  if (!first) return;
  std::vector<std::string> known(used_.begin(), used_.end());
  for (const auto& k : known)
    if (unit_mismatch(first_key, k)) fail_unknown(first_key, k);
  const std::string near = nearest_name(first_key, known);
  if (!near.empty()) fail_unknown(first_key, near);
  std::string list;
  for (const auto& u : used_) list += (list.empty() ? "" : ", ") + u;
  const auto& src = first->source().begin;
  throw InputError(
      located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
              std::string(first->is_table() || first->is_array_of_tables() ? "unknown table '"
                                                                           : "unknown key '") +
                  full_key(first_key) + "'" + (list.empty() ? "" : " (known here: " + list + ")")));
}

}  // namespace lathectl::io
