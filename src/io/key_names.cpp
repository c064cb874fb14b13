// The scenario reader's text: its numbers and lists as messages write them, the units written in
// key names (unit_of_key, unit_mismatch) and the nearest known name (nearest_name).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lathectl/io/toml_reader.hpp"
#include "toml_reader_text.hpp"

namespace lathectl::io {

namespace detail {

std::string fmt_num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string quoted_list(const std::vector<std::string>& choices) {
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  return list;
}

}  // namespace detail

namespace {

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

}  // namespace

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

}  // namespace lathectl::io
