#include "lathectl/io/linuxcnc_ini.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {
namespace {

std::string_view ini_trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string at_key(const LinuxcncIni::Entry& e) {
  return "[" + e.section + "]" + e.key + " = '" + e.value + "'";
}

[[noreturn]] void bad(const LinuxcncIni& ini, const LinuxcncIni::Entry& e, const std::string& why) {
  throw InputError(located(ini.file, e.line, 0, at_key(e) + ": " + why));
}

// A finite number, the whole value.
std::optional<double> number(const LinuxcncIni& ini, std::string_view section,
                             std::string_view key, double scale, bool positive) {
  const auto* e = ini.find(section, key);
  if (e == nullptr) return std::nullopt;
  double v = 0.0;
  const char* b = e->value.data();
  const char* end = b + e->value.size();
  if (b != end && *b == '+') ++b;
  const auto r = std::from_chars(b, end, v);
  if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) bad(ini, *e, "not a number");
  if (positive && !(v > 0.0)) bad(ini, *e, "must be > 0");
  return v * scale;
}

}  // namespace

const LinuxcncIni::Entry* LinuxcncIni::find(std::string_view section, std::string_view key) const {
  for (const auto& e : entries)
    if (e.section == section && e.key == key) return &e;
  return nullptr;
}

LinuxcncIni parse_linuxcnc_ini(std::string_view text, const std::string& file) {
  LinuxcncIni ini;
  ini.file = file;
  std::string section;
  int line = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view l = ini_trim(text.substr(pos, end - pos));
    pos = end + 1;
    ++line;
    if (l.empty() || l.front() == '#' || l.front() == ';') continue;
    if (l.front() == '[') {
      const std::size_t close = l.find(']');
      section = close == std::string_view::npos ? std::string() : std::string(l.substr(1, close - 1));
      continue;
    }
    // A line without '=', or before the first section: LinuxCNC passes over it, and so do we
    // (what lathectl reads is checked by lathe_machine).
    const std::size_t eq = l.find('=');
    if (eq == std::string_view::npos || eq == 0 || section.empty()) continue;
    ini.entries.push_back({section, std::string(ini_trim(l.substr(0, eq))),
                           std::string(ini_trim(l.substr(eq + 1))), line});
  }
  return ini;
}

LatheMachine lathe_machine(const LinuxcncIni& ini) {
  LatheMachine m;
  const auto* units = ini.find("TRAJ", "LINEAR_UNITS");
  if (units == nullptr)
    throw InputError(ini.file + ": [TRAJ]LINEAR_UNITS missing: the machine's length unit "
                                "(mm or inch)");
  std::string u = units->value;
  std::transform(u.begin(), u.end(), u.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // LinuxCNC's IniFile::FindLinearUnits table.
  if (u == "mm" || u == "metric" || u == "millimeter" || u == "millimeters")
    m.unit_mm = 1.0;
  else if (u == "in" || u == "inch" || u == "imperial" || u == "inches")
    m.unit_mm = 25.4;
  else
    bad(ini, *units, "LinuxCNC's linear units are mm, metric, in, inch or imperial");
  const double s = m.unit_mm;
  m.x_min = number(ini, "AXIS_X", "MIN_LIMIT", s, false);
  m.x_max = number(ini, "AXIS_X", "MAX_LIMIT", s, false);
  m.z_min = number(ini, "AXIS_Z", "MIN_LIMIT", s, false);
  m.z_max = number(ini, "AXIS_Z", "MAX_LIMIT", s, false);
  for (const char* axis : {"AXIS_X", "AXIS_Z"}) {
    const auto lo = axis[5] == 'X' ? m.x_min : m.z_min;
    const auto hi = axis[5] == 'X' ? m.x_max : m.z_max;
    if (lo && hi && *lo > *hi) bad(ini, *ini.find(axis, "MIN_LIMIT"), "above its MAX_LIMIT");
  }
  const auto least = [&](const char* key_traj, const char* key_axis) {
    std::optional<double> v;
    for (const auto& o : {number(ini, "TRAJ", key_traj, s, true),
                          number(ini, "AXIS_X", key_axis, s, true),
                          number(ini, "AXIS_Z", key_axis, s, true)})
      if (o) v = v ? std::min(*v, *o) : *o;
    return v;
  };
  m.max_velocity_mm_s = least("MAX_LINEAR_VELOCITY", "MAX_VELOCITY");
  m.max_acceleration_mm_s2 = least("MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION");
  if (const auto* t = ini.find("EMCIO", "TOOL_TABLE")) m.tool_table = t->value;
  return m;
}

}  // namespace lathectl::io
