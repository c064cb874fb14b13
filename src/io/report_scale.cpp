// The report's plots' numbers and axis scales: locale-independent numbers, 1-2-5 and decade ticks,
// ranges (report_plot.hpp).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <vector>

#include "report_plot.hpp"

namespace lathectl::io::detail {

// Locale-independent (std::to_chars), unlike printf, so a program that calls setlocale() cannot
// turn the decimal point of an SVG coordinate into a comma.
std::string fixed(double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed, decimals);
  if (r.ec != std::errc{}) return "0";
  return std::string(buf, r.ptr);
}

// %g-like with a compact exponent: 1.5e+06 → 1.5e6, 2e-05 → 2e-5.
std::string general(double v, int precision) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, precision);
  if (r.ec != std::errc{}) return "0";
  std::string s(buf, r.ptr);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::string mantissa = s.substr(0, e);
  std::string exponent = s.substr(e + 1);
  bool negative = false;
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) {
    negative = exponent[0] == '-';
    exponent.erase(0, 1);
  }
  const auto nz = exponent.find_first_not_of('0');
  exponent = nz == std::string::npos ? "0" : exponent.substr(nz);
  return mantissa + (negative ? "e-" : "e") + exponent;
}

// One SVG coordinate, 0.1 px resolution, no trailing ".0", never "-0".
std::string coord(double v) {
  if (!std::isfinite(v)) return "0";  // unreachable by construction; never emit nan/inf
  std::string s = fixed(std::round(v * 10.0) / 10.0, 1);
  if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
  if (s == "-0") s = "0";
  return s;
}

// Tick label for v on an axis [lo, hi] with the given (1-2-5) step: plain decimals for ordinary
// magnitudes, just enough significant digits otherwise.
std::string tick_label(double v, double step, double lo, double hi) {
  if (std::abs(v) < step * 1e-6) return "0";
  const double mag = std::max(std::abs(lo), std::abs(hi));
  const double step_exp = std::floor(std::log10(step) + 1e-9);
  if (mag >= 1e-3 && mag < 1e6 && step >= 1e-6) {
    const int decimals = step_exp < 0.0 ? static_cast<int>(-step_exp) : 0;
    return fixed(v, decimals);
  }
  const double mag_exp = std::floor(std::log10(mag) + 1e-9);
  const int digits = std::clamp(static_cast<int>(mag_exp - step_exp) + 1, 1, 15);
  return general(v, digits);
}

double nice_step(double raw) {
  if (!(raw > 0.0) || !std::isfinite(raw)) return 1.0;
  const double exp10 = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / exp10;
  const double n = f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0;  // nearest 1-2-5
  return n * exp10;
}

Ticks make_ticks(double lo, double hi, double target_count) {
  Ticks t;
  t.step = nice_step((hi - lo) / target_count);
  const double start = std::ceil(lo / t.step - 1e-9) * t.step;
  for (int i = 0; i < 100; ++i) {
    double v = start + static_cast<double>(i) * t.step;
    if (v > hi + t.step * 1e-9) break;
    if (std::abs(v) < t.step * 1e-9) v = 0.0;
    t.values.push_back(v);
  }
  return t;
}

// Widens a degenerate (constant, or so narrow that pixel maths would underflow) range; pads a
// proper one by `pad_fraction` of its span on each side.
Range widen(double lo, double hi, double pad_fraction) {
  constexpr double kTiny = 1e-200;
  const double span = hi - lo;
  const double scale = std::max(std::abs(lo), std::abs(hi));
  if (span > scale * 1e-12 && span > kTiny) {
    return {lo - span * pad_fraction, hi + span * pad_fraction};
  }
  const double pad = scale > kTiny ? scale * 0.1 : 1.0;
  return {lo - pad, hi + pad};
}

// Decade ticks on a log10 axis [lo, hi] (in decades); 2 and 5 between them when the axis spans
// fewer than three decades.
Ticks log_ticks(double lo, double hi) {
  Ticks t;
  t.step = 1.0;
  const bool fine = hi - lo < 3.0;
  for (double d = std::floor(lo); d <= std::ceil(hi) && t.values.size() < 60; d += 1.0) {
    for (const double m : {1.0, 2.0, 5.0}) {
      if (m > 1.0 && !fine) continue;
      const double v = d + std::log10(m);
      if (v >= lo - 1e-9 && v <= hi + 1e-9) t.values.push_back(v);
    }
  }
  return t;
}

std::string log_tick_label(double decades) {
  const double v = std::pow(10.0, decades);
  if (v < 1e-4 || v >= 1e6) return general(v, 2);
  const double d = std::floor(decades + 1e-9);
  return fixed(v, d < 0.0 ? static_cast<int>(-d) : 0);
}

}  // namespace lathectl::io::detail
