#include "lathectl/io/canon.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {
namespace {

constexpr std::string_view kMarker = "lathectl-line ";
constexpr double kInchMm = 25.4;

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

namespace {

// One command of the interpreter's output, "<seq> N<...> NAME(args)": its name and arguments;
// false for any other line ("executing", messages).
bool command(std::string_view ln, std::string_view& name, std::string_view& inner) {
  std::size_t i = 0;
  while (i < ln.size() && ln[i] >= '0' && ln[i] <= '9') ++i;
  if (i == 0) return false;
  ln = trim(ln.substr(i));
  if (ln.empty() || ln.front() != 'N') return false;
  const std::size_t sp = ln.find_first_of(" \t");
  if (sp == std::string_view::npos) return false;
  ln = trim(ln.substr(sp));
  const std::size_t open = ln.find('(');
  if (open == std::string_view::npos || ln.back() != ')') return false;
  name = ln.substr(0, open);
  inner = ln.substr(open + 1, ln.size() - open - 2);
  return true;
}

// Reads the commands one by one into moves, each a copy of the modal state.
class CanonParser {
 public:
  CanonParser(const std::string& label, double x, double z,
              std::optional<ToolChangePosition> tool_change)
      : label_(label), tool_change_(tool_change), x_(x), z_(z) {}

  void line(std::string_view ln) {
    ++out_line_;
    std::string_view name, inner;
    if (!command(ln, name, inner)) return;
    if (modal(name, inner)) return;
    const bool known = name == "SET_G5X_OFFSET" || name == "SET_G92_OFFSET" ||
                       name == "USE_TOOL_LENGTH_OFFSET" || name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" ||
                       name == "ARC_FEED" || name == "SET_FEED_MODE" || name == "SET_FEED_RATE" ||
                       name == "SET_SPINDLE_MODE" || name == "SET_SPINDLE_SPEED" ||
                       name == "START_SPEED_FEED_SYNC" || name == "SELECT_TOOL" ||
                       name == "CHANGE_TOOL";
    if (!known) return;
    Args a;
    if (!numbers(inner, a)) fail(std::string(name) + ": arguments are not numbers");
    if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED")
      straight(name, a);
    else if (name == "ARC_FEED")
      arc(name, a);
    else
      setting(name, a);
  }
  CanonProgram& program() { return prog_; }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(label_ + ": interpreter output line " + std::to_string(out_line_) + ": " +
                     what);
  }
  void need(std::string_view name, const Args& a, std::size_t k) const {
    if (a.n < k) fail(std::string(name) + ": expected " + std::to_string(k) + " arguments");
  }

  // The commands without numbers to read: comments (the line marker, cutter compensation), units,
  // plane, blending, the spindle, and what stops motion. True when the command is done with.
  bool modal(std::string_view name, std::string_view inner) {
    if (name == "COMMENT") {
      const std::size_t at = inner.find(kMarker);
      if (at != std::string_view::npos) {
        const std::string_view num = inner.substr(at + kMarker.size());
        int v = 0;
        const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
        if (r.ec == std::errc() && v > 0) state_.line = v;
      } else if (inner.find("cutter radius compensation on") != std::string_view::npos) {
        state_.compensated = true;
      } else if (inner.find("cutter radius compensation off") != std::string_view::npos) {
        state_.compensated = false;
      }
      return true;
    }
    if (name == "USE_LENGTH_UNITS") {  // G20 / G21 (CANON_UNITS_CM: no G code sets it)
      state_.unit_mm = inner.find("INCHES") != std::string_view::npos ? kInchMm
                       : inner.find("CM") != std::string_view::npos   ? 10.0
                                                                      : 1.0;
      return true;
    }
    if (name == "SELECT_PLANE") {
      plane_xz_ = inner.find("CANON_PLANE_XZ") != std::string_view::npos;
      return true;
    }
    if (name == "SET_MOTION_CONTROL_MODE") {
      if (inner.find("CANON_CONTINUOUS") != std::string_view::npos) {
        const std::size_t comma = inner.find(',');
        Args a;
        if (comma == std::string_view::npos || !numbers(inner.substr(comma + 1), a) || a.n < 1)
          state_.blend_tol_mm = 0.0;
        else
          state_.blend_tol_mm = std::max(0.0, a.v[0]) * state_.unit_mm;
      } else {
        state_.blend_tol_mm = -1.0;
      }
      return true;
    }
    // What LinuxCNC's task runs only once motion is done (emctaskmain.cc,
    // emcTaskCheckPreconditions: WAITING_FOR_MOTION): no blend across these.
    if (name == "DWELL" || name == "CHANGE_TOOL" || name == "PROGRAM_STOP" ||
        name == "OPTIONAL_PROGRAM_STOP" || name == "USER_DEFINED_FUNCTION" ||
        name == "SET_SPINDLE_SPEED" || name == "FLOOD_ON" || name == "FLOOD_OFF" ||
        name == "MIST_ON" || name == "MIST_OFF" || name == "USE_TOOL_LENGTH_OFFSET" ||
        name == "SET_G5X_OFFSET" || name == "SET_G92_OFFSET" || name == "SET_XY_ROTATION" ||
        name == "MESSAGE" || name == "STRAIGHT_PROBE" || name == "RIGID_TAP") {
      stop_pending_ = true;  // SET_SPINDLE_SPEED is also read below
    }
    if (name == "STOP_SPEED_FEED_SYNCH") {
      state_.synced = false;
      return true;
    }
    if (name == "START_SPINDLE_CLOCKWISE" || name == "START_SPINDLE_COUNTERCLOCKWISE") {
      state_.spindle_on = true;
      stop_pending_ = true;
      return true;
    }
    if (name == "STOP_SPINDLE_TURNING") {
      state_.spindle_on = false;
      stop_pending_ = true;
      return true;
    }
    return false;
  }

  void straight(std::string_view name, const Args& a) {
    need(name, a, 3);
    CanonMove m = state_;
    m.kind = name == "STRAIGHT_TRAVERSE" ? CanonMove::Kind::Traverse : CanonMove::Kind::Line;
    m.x0 = x_;
    m.z0 = z_;
    const double u = state_.unit_mm;
    m.x1 = x_ = a.v[0] * u;
    m.z1 = z_ = a.v[2] * u;
    if (std::abs(a.v[1]) > 1e-9) fail("a move in Y: a lathe program moves in X and Z only");
    m.stop_before = std::exchange(stop_pending_, false);
    prog_.moves.push_back(m);
  }

  void arc(std::string_view name, const Args& a) {
    need(name, a, 5);
    if (!plane_xz_) fail("ARC_FEED: an arc outside the XZ plane (a lathe program turns in G18)");
    CanonMove m = state_;
    m.kind = CanonMove::Kind::Arc;
    m.x0 = x_;
    m.z0 = z_;
    const double u = state_.unit_mm;
    m.z1 = z_ = a.v[0] * u;
    m.x1 = x_ = a.v[1] * u;
    m.zc = a.v[2] * u;
    m.xc = a.v[3] * u;
    m.rotation = static_cast<int>(a.v[4]);
    if (m.rotation == 0) fail("ARC_FEED: rotation 0");
    const double r0 = std::hypot(m.x0 - m.xc, m.z0 - m.zc);
    const double r1 = std::hypot(m.x1 - m.xc, m.z1 - m.zc);
    if (!(r0 > 0.0) || std::abs(r0 - r1) > 1e-3 * std::max(1.0, r0))
      fail("ARC_FEED: start and end not on one circle");
    m.stop_before = std::exchange(stop_pending_, false);
    prog_.moves.push_back(m);
  }

  void offsets() {
    state_.offset_x = g5x_[0] + g92_[0] + tlo_[0];
    state_.offset_z = g5x_[1] + g92_[1] + tlo_[1];
  }

  // The modal state the numbered commands set: feed mode and rate, spindle, synchronisation,
  // offsets, tool.
  void setting(std::string_view name, const Args& a) {
    const double u = state_.unit_mm;
    if (name == "SET_FEED_MODE") {
      need(name, a, 2);
      state_.per_rev = a.v[1] > 0.5;
    } else if (name == "SET_FEED_RATE") {
      need(name, a, 1);
      state_.feed = a.v[0] * u;  // in/min, in/rev under G20
    } else if (name == "SET_SPINDLE_MODE") {
      need(name, a, 2);
      state_.css = a.v[1] > 0.0;
      state_.css_max_rpm = a.v[1];
    } else if (name == "SET_SPINDLE_SPEED") {
      need(name, a, 2);
      // G96 under G20: surface feet per minute (LinuxCNC's canon: 12 in per foot).
      state_.speed = state_.css && u == kInchMm ? a.v[1] * kInchMm * 12.0 / 1000.0 : a.v[1];
    } else if (name == "START_SPEED_FEED_SYNC") {
      need(name, a, 1);
      state_.synced = true;
      state_.pitch_mm = a.v[0] * u;
    } else if (name == "SET_G5X_OFFSET") {
      need(name, a, 4);
      g5x_ = {a.v[1] * u, a.v[3] * u};
      offsets();
    } else if (name == "SET_G92_OFFSET") {
      need(name, a, 3);
      g92_ = {a.v[0] * u, a.v[2] * u};
      offsets();
    } else if (name == "USE_TOOL_LENGTH_OFFSET") {
      need(name, a, 3);
      tlo_ = {a.v[0] * u, a.v[2] * u};
      offsets();
    } else if (name == "SELECT_TOOL") {
      need(name, a, 1);
      // A pocket number LinuxCNC's tool table can hold; anything else (a fuzzer's 2.9e54) would
      // be undefined behaviour in the conversion to int.
      if (!(a.v[0] >= 0.0 && a.v[0] <= 99999.0))
        fail("SELECT_TOOL: tool number " + std::to_string(a.v[0]) + " outside [0, 99999]");
      selected_ = static_cast<int>(a.v[0]);
    } else if (name == "CHANGE_TOOL") {
      if (tool_change_) travel_to_tool_change();
      // T only prepares a tool; M6 puts it in the spindle (LinuxCNC's iocontrol tool-number, the
      // pin the LinuxCNC plant reads). CHANGE_TOOL's argument is the tool table's pocket/index
      // (SELECT_TOOL(10) then CHANGE_TOOL(3) in tests/optimize/canon_example.txt), not the tool
      // number: the tool now in the spindle is the last one selected.
      state_.tool = selected_;
    }
  }

  // LinuxCNC's task before the change (emccanon.cc CHANGE_TOOL): flush_segments(), then one
  // EMC_TRAJ_LINEAR_MOVE of type TOOLCHANGE to the position, in machine coordinates, at
  // getStraightVelocity/Acceleration (a G0's), all axes together; the tool load waits for it.
  // The interpreter then takes the machine's position as its own (convert_tool_change:
  // toolchange_flag), so the next move starts there.
  void travel_to_tool_change() {
    CanonMove m = state_;
    m.kind = CanonMove::Kind::Traverse;
    m.tool_change = true;
    m.synced = false;
    m.x0 = x_;
    m.z0 = z_;
    m.x1 = tool_change_->x_mm - state_.offset_x;
    m.z1 = tool_change_->z_mm - state_.offset_z;
    if (std::hypot(m.x1 - m.x0, m.z1 - m.z0) <= 1e-9) return;
    x_ = m.x1;
    z_ = m.z1;
    m.stop_before = true;
    stop_pending_ = true;  // the change itself waits for motion
    prog_.moves.push_back(m);
  }

  const std::string& label_;
  std::optional<ToolChangePosition> tool_change_;
  CanonProgram prog_;
  CanonMove state_;  // the modal state, copied into each move
  double x_, z_;
  int out_line_ = 0;
  int selected_ = 0;  // the last SELECT_TOOL (T word): in the spindle only after CHANGE_TOOL (M6)
  bool stop_pending_ = true;  // the first move starts from rest
  bool plane_xz_ = false;
  std::array<double, 2> g5x_{}, g92_{}, tlo_{};  // x, z of each offset
};

}  // namespace

CanonProgram parse_canon(std::string_view text, const std::string& label, double start_x_mm,
                         double start_z_mm, std::optional<ToolChangePosition> tool_change) {
  CanonParser parser(label, start_x_mm, start_z_mm, tool_change);
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    parser.line(trim(text.substr(pos, end - pos)));
    pos = end + 1;
  }
  return std::move(parser.program());
}

}  // namespace lathectl::io
