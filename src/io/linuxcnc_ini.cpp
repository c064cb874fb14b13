#include "lathectl/io/linuxcnc_ini.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

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

// [EMCIO]TOOL_CHANGE_POSITION: LinuxCNC's task reads "X Y Z", "X Y Z A B C" or nine numbers
// (taskclass.cc readToolChange, sscanf); a lathe takes X and Z.
void tool_change_position(const LinuxcncIni& ini, LatheMachine& m) {
  const auto* e = ini.find("EMCIO", "TOOL_CHANGE_POSITION");
  if (e == nullptr) return;
  std::vector<double> v;
  std::string_view rest = e->value;
  while (!(rest = ini_trim(rest)).empty()) {
    std::size_t n = 0;
    while (n < rest.size() && !std::isspace(static_cast<unsigned char>(rest[n]))) ++n;
    const char* b = rest.data();
    const char* end = b + n;
    if (*b == '+') ++b;
    double d = 0.0;
    const auto r = std::from_chars(b, end, d);
    if (r.ec != std::errc() || r.ptr != end || !std::isfinite(d))
      bad(ini, *e, "not a number: '" + std::string(rest.substr(0, n)) + "' (X Y Z [A B C [U V W]])");
    v.push_back(d);
    rest.remove_prefix(n);
  }
  if (v.size() < 3) bad(ini, *e, "expected X Y Z [A B C [U V W]] (machine coordinates)");
  m.tool_change_x = v[0] * m.unit_mm;
  m.tool_change_z = v[2] * m.unit_mm;
}

// The joint of `axis` (X or Z) as trivkins numbers them: the letters of [KINS]KINEMATICS's
// coordinates= in order, else the identity X Y Z A B C U V W.
int joint_of(const LinuxcncIni& ini, char axis) {
  std::string k;
  if (const auto* e = ini.find("KINS", "KINEMATICS")) k = e->value;
  std::transform(k.begin(), k.end(), k.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const auto at = k.find("COORDINATES=");
  if (at == std::string::npos) return axis == 'X' ? 0 : 2;
  int j = 0;
  for (std::size_t i = at + 12; i < k.size() && !std::isspace(static_cast<unsigned char>(k[i])); ++i) {
    if (k[i] == axis) return j;
    if (std::isalpha(static_cast<unsigned char>(k[i]))) ++j;
  }
  return axis == 'X' ? 0 : 2;
}

void home(const LinuxcncIni& ini, LatheMachine& m) {
  for (const char axis : {'X', 'Z'}) {
    const std::string joint = "JOINT_" + std::to_string(joint_of(ini, axis));
    (void)number(ini, joint, "HOME_OFFSET", m.unit_mm, false);
    (axis == 'X' ? m.home_x_key : m.home_z_key) = "[" + joint + "]HOME";
    const auto h = number(ini, joint, "HOME", m.unit_mm, false);
    if (!h) continue;
    (axis == 'X' ? m.home_x : m.home_z) = *h;
    (axis == 'X' ? m.home_x_line : m.home_z_line) = ini.find(joint, "HOME")->line;
  }
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
  tool_change_position(ini, m);
  home(ini, m);
  return m;
}

}  // namespace lathectl::io
