#include "lathectl/io/canon.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {
namespace {

constexpr std::string_view kMarker = "lathectl-line ";

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

// The numbers of "NAME(a, b c, d)": separated by commas and/or blanks (SET_SPINDLE_MODE prints
// "(0 2000.0000)", USE_TOOL_LENGTH_OFFSET mixes both). At most 12 are kept.
struct Args {
  std::array<double, 12> v{};
  std::size_t n = 0;
};
bool numbers(std::string_view s, Args& out) {
  out.n = 0;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == ',' || s[i] == '\t')) ++i;
    if (i >= s.size()) break;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != ',' && s[j] != '\t') ++j;
    double d = 0.0;
    const auto* b = s.data() + i;
    const auto* e = s.data() + j;
    if (*b == '+') ++b;
    const auto r = std::from_chars(b, e, d);
    if (r.ec != std::errc() || r.ptr != e || !std::isfinite(d)) return false;
    if (out.n < out.v.size()) out.v[out.n++] = d;
    i = j;
  }
  return true;
}

}  // namespace

std::string canon_line_marker(int line) {
  return std::string(kMarker) + std::to_string(line);
}

CanonProgram parse_canon(std::string_view text, const std::string& label, double start_x_mm,
                         double start_z_mm) {
  CanonProgram prog;
  CanonMove state;  // the modal state, copied into each move
  double x = start_x_mm, z = start_z_mm;
  int out_line = 0;
  bool stop_pending = true;  // the first move starts from rest
  bool plane_xz = false;
  std::array<double, 2> g5x{}, g92{}, tlo{};  // x, z of each offset
  auto fail = [&](const std::string& what) {
    throw InputError(label + ": interpreter output line " + std::to_string(out_line) + ": " + what);
  };
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view ln = trim(text.substr(pos, end - pos));
    pos = end + 1;
    ++out_line;
    // "<seq> N<...> NAME(args)"
    std::size_t i = 0;
    while (i < ln.size() && ln[i] >= '0' && ln[i] <= '9') ++i;
    if (i == 0) continue;  // not a command line ("executing", messages)
    ln = trim(ln.substr(i));
    if (ln.empty() || ln.front() != 'N') continue;
    const std::size_t sp = ln.find_first_of(" \t");
    if (sp == std::string_view::npos) continue;
    ln = trim(ln.substr(sp));
    const std::size_t open = ln.find('(');
    if (open == std::string_view::npos || ln.back() != ')') continue;
    const std::string_view name = ln.substr(0, open);
    const std::string_view inner = ln.substr(open + 1, ln.size() - open - 2);
    if (name == "COMMENT") {
      const std::size_t at = inner.find(kMarker);
      if (at != std::string_view::npos) {
        const std::string_view num = inner.substr(at + kMarker.size());
        int v = 0;
        const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
        if (r.ec == std::errc() && v > 0) state.line = v;
      } else if (inner.find("cutter radius compensation on") != std::string_view::npos) {
        state.compensated = true;
      } else if (inner.find("cutter radius compensation off") != std::string_view::npos) {
        state.compensated = false;
      }
      continue;
    }
    if (name == "USE_LENGTH_UNITS") {
      if (inner.find("MM") == std::string_view::npos)
        fail(
            "the program works in inches (G20); lathectl optimize reads millimetre programs (G21)");
      continue;
    }
    if (name == "SELECT_PLANE") {
      plane_xz = inner.find("CANON_PLANE_XZ") != std::string_view::npos;
      continue;
    }
    if (name == "SET_MOTION_CONTROL_MODE") {
      if (inner.find("CANON_CONTINUOUS") != std::string_view::npos) {
        const std::size_t comma = inner.find(',');
        Args a;
        if (comma == std::string_view::npos || !numbers(inner.substr(comma + 1), a) || a.n < 1)
          state.blend_tol_mm = 0.0;
        else
          state.blend_tol_mm = std::max(0.0, a.v[0]);
      } else {
        state.blend_tol_mm = -1.0;
      }
      continue;
    }
    // What LinuxCNC's task runs only once motion is done (emctaskmain.cc,
    // emcTaskCheckPreconditions: WAITING_FOR_MOTION): no blend across these.
    if (name == "DWELL" || name == "CHANGE_TOOL" || name == "PROGRAM_STOP" ||
        name == "OPTIONAL_PROGRAM_STOP" || name == "USER_DEFINED_FUNCTION" ||
        name == "SET_SPINDLE_SPEED" || name == "FLOOD_ON" || name == "FLOOD_OFF" ||
        name == "MIST_ON" || name == "MIST_OFF" || name == "USE_TOOL_LENGTH_OFFSET" ||
        name == "SET_G5X_OFFSET" || name == "SET_G92_OFFSET" || name == "SET_XY_ROTATION" ||
        name == "MESSAGE" || name == "STRAIGHT_PROBE" || name == "RIGID_TAP") {
      stop_pending = true;  // SET_SPINDLE_SPEED is also read below
    }
    if (name == "STOP_SPEED_FEED_SYNCH") {
      state.synced = false;
      continue;
    }
    if (name == "START_SPINDLE_CLOCKWISE" || name == "START_SPINDLE_COUNTERCLOCKWISE") {
      state.spindle_on = true;
      stop_pending = true;
      continue;
    }
    if (name == "STOP_SPINDLE_TURNING") {
      state.spindle_on = false;
      stop_pending = true;
      continue;
    }
    const bool known = name == "SET_G5X_OFFSET" || name == "SET_G92_OFFSET" ||
                       name == "USE_TOOL_LENGTH_OFFSET" || name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" ||
                       name == "ARC_FEED" || name == "SET_FEED_MODE" || name == "SET_FEED_RATE" ||
                       name == "SET_SPINDLE_MODE" || name == "SET_SPINDLE_SPEED" ||
                       name == "START_SPEED_FEED_SYNC" || name == "SELECT_TOOL";
    if (!known) continue;
    Args a;
    if (!numbers(inner, a)) fail(std::string(name) + ": arguments are not numbers");
    auto need = [&](std::size_t k) {
      if (a.n < k) fail(std::string(name) + ": expected " + std::to_string(k) + " arguments");
    };
    if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED") {
      need(3);
      CanonMove m = state;
      m.kind = name == "STRAIGHT_TRAVERSE" ? CanonMove::Kind::Traverse : CanonMove::Kind::Line;
      m.x0 = x;
      m.z0 = z;
      m.x1 = x = a.v[0];
      m.z1 = z = a.v[2];
      if (std::abs(a.v[1]) > 1e-9) fail("a move in Y: a lathe program moves in X and Z only");
      m.stop_before = std::exchange(stop_pending, false);
      prog.moves.push_back(m);
    } else if (name == "ARC_FEED") {
      need(5);
      if (!plane_xz) fail("ARC_FEED: an arc outside the XZ plane (a lathe program turns in G18)");
      CanonMove m = state;
      m.kind = CanonMove::Kind::Arc;
      m.x0 = x;
      m.z0 = z;
      m.z1 = z = a.v[0];
      m.x1 = x = a.v[1];
      m.zc = a.v[2];
      m.xc = a.v[3];
      m.rotation = static_cast<int>(a.v[4]);
      if (m.rotation == 0) fail("ARC_FEED: rotation 0");
      const double r0 = std::hypot(m.x0 - m.xc, m.z0 - m.zc);
      const double r1 = std::hypot(m.x1 - m.xc, m.z1 - m.zc);
      if (!(r0 > 0.0) || std::abs(r0 - r1) > 1e-3 * std::max(1.0, r0))
        fail("ARC_FEED: start and end not on one circle");
      m.stop_before = std::exchange(stop_pending, false);
      prog.moves.push_back(m);
    } else if (name == "SET_FEED_MODE") {
      need(2);
      state.per_rev = a.v[1] > 0.5;
    } else if (name == "SET_FEED_RATE") {
      need(1);
      state.feed = a.v[0];
    } else if (name == "SET_SPINDLE_MODE") {
      need(2);
      state.css = a.v[1] > 0.0;
      state.css_max_rpm = a.v[1];
    } else if (name == "SET_SPINDLE_SPEED") {
      need(2);
      state.speed = a.v[1];
    } else if (name == "START_SPEED_FEED_SYNC") {
      need(1);
      state.synced = true;
      state.pitch_mm = a.v[0];
    } else if (name == "SET_G5X_OFFSET") {
      need(4);
      g5x = {a.v[1], a.v[3]};
      state.offset_x = g5x[0] + g92[0] + tlo[0];
      state.offset_z = g5x[1] + g92[1] + tlo[1];
    } else if (name == "SET_G92_OFFSET") {
      need(3);
      g92 = {a.v[0], a.v[2]};
      state.offset_x = g5x[0] + g92[0] + tlo[0];
      state.offset_z = g5x[1] + g92[1] + tlo[1];
    } else if (name == "USE_TOOL_LENGTH_OFFSET") {
      need(3);
      tlo = {a.v[0], a.v[2]};
      state.offset_x = g5x[0] + g92[0] + tlo[0];
      state.offset_z = g5x[1] + g92[1] + tlo[1];
    } else if (name == "SELECT_TOOL") {
      need(1);
      // A pocket number LinuxCNC's tool table can hold; anything else (a fuzzer's 2.9e54) would
      // be undefined behaviour in the conversion to int.
      if (!(a.v[0] >= 0.0 && a.v[0] <= 99999.0))
        fail("SELECT_TOOL: tool number " + std::to_string(a.v[0]) + " outside [0, 99999]");
      state.tool = static_cast<int>(a.v[0]);
    }
  }
  return prog;
}

}  // namespace lathectl::io
