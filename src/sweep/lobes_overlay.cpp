// [report] of a sweep (docs/sweep.md): the stability lobes of a machine file, computed by the
// code of `lathectl lobes` (systems::b_chatter::compute_lobes, lobe_curves), drawn over the heat
// maps of the speed and depth keys, and each grid point's simulated verdict set against them.
#include <algorithm>
#include <cmath>
#include <limits>

#include "lathectl/io/errors.hpp"
#include "sweep/engine.hpp"
#include "systems/b_chatter/lobes_outputs.hpp"

namespace lathectl::sweep {
namespace {

namespace b = systems::b_chatter;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A grid point is "away from the boundary" when its depth lies beyond ±25 % of the limit.
constexpr double kClear = 0.25;

// The lobes' limit depth b [mm] as the depth key's value (LobesOverlay).
double as_depth_key(const LobesOverlay& o, double b_mm) {
  if (!(o.depth_exponent > 0.0)) return b_mm;
  return o.depth_reference * std::pow(b_mm / o.depth_reference, 1.0 / (1.0 - o.depth_exponent));
}

// Linear interpolation of a curve (speeds increasing) at a speed; NaN outside or next to a gap.
double at_speed(const b::LobeCurve& c, double n) {
  const auto& s = c.speed_rpm;
  if (s.empty()) return kNaN;
  const auto it = std::upper_bound(s.begin(), s.end(), n);
  if (it == s.begin() || it == s.end()) return n == s.back() ? c.depth_mm.back() : kNaN;
  const auto i = static_cast<std::size_t>(it - s.begin());
  const double f = (n - s[i - 1]) / (s[i] - s[i - 1]);
  return c.depth_mm[i - 1] + f * (c.depth_mm[i] - c.depth_mm[i - 1]);
}

struct Tally {
  std::size_t compared = 0, agree = 0, clear = 0, clear_agree = 0;
  void add(bool sim, double y, double limit) {
    if (!std::isfinite(limit)) return;
    const bool lobes = y > limit, ok = lobes == sim;
    ++compared;
    agree += ok;
    if (std::abs(y / limit - 1.0) > kClear) ++clear, clear_agree += ok;
  }
  // "k of n (p %)": the grid points whose verdicts match, of those compared.
  static std::string share(std::size_t k, std::size_t n) {
    return std::to_string(k) + " of " + std::to_string(n) +
           (n ? " (" + std::to_string(std::lround(100.0 * double(k) / double(n))) + " %)" : "");
  }
  void report(const std::string& method, io::Report& rep) const {
    rep.metrics.push_back({"agreement with the lobes, " + method, share(agree, compared)});
    rep.metrics.push_back({"… away from the boundary (beyond ±25 % of the limit)",
                           share(clear_agree, clear)});
  }
};

std::string num(double v) { return std::isfinite(v) ? to_text(std::round(v * 1e4) / 1e4) : "—"; }

// The lines over one heat map: the curves with the depth converted, on the map's axes.
std::vector<io::HeatMapLine> lines(const LobesOverlay& o, const b::LobeCurves& c, bool speed_x) {
  const auto line = [&](const b::LobeCurve& k, std::string name, std::string color, bool dashed,
                        bool points) {
    io::HeatMapLine l{std::move(name), {}, {}, std::move(color), dashed, points};
    for (std::size_t i = 0; i < k.speed_rpm.size(); ++i) {
      const double y = as_depth_key(o, k.depth_mm[i]);
      l.x.push_back(speed_x ? k.speed_rpm[i] : y);
      l.y.push_back(speed_x ? y : k.speed_rpm[i]);
    }
    return l;
  };
  return {line(c.envelope, "lobes, frequency domain", "#000", false, false),
          line(c.chart, "lobes, semi-discretization chart", "#2ca02c", true, false),
          line(c.sd, "lobes, semi-discretization (bisection)", "#7b2d8e", false, true)};
}

}  // namespace

void check_lobes_machine(const Spec& spec) {
  if (!spec.lobes) return;
  try {
    (void)b::load_lobes_input(spec.lobes->machine.string());
  } catch (const io::InputError& e) {
    throw io::InputError(io::located(spec.file, spec.lobes->machine_at.line,
                                     spec.lobes->machine_at.column,
                                     "key 'report.lobes': " + std::string(e.what())));
  }
}

void lobes_overlay(const Spec& spec, const std::vector<double>& chatter, io::Report& rep) {
  const LobesOverlay& o = *spec.lobes;
  const auto in = b::load_lobes_input(o.machine.string());
  const auto run = b::compute_lobes(in);
  const auto curves = b::lobe_curves(in, run);
  const bool speed_x = spec.grid[1].key == o.speed;  // the heat maps: grid[1] across
  for (auto& h : rep.heat_maps) {
    for (const auto& v : spec.grid[1].values) h.x_values.push_back(number_of(v));
    for (const auto& v : spec.grid[0].values) h.y_values.push_back(number_of(v));
    h.lines = lines(o, curves, speed_x);
  }
  rep.notes.push_back(
      "The lines are the stability lobes of " + o.machine.filename().string() +
      " (as `lathectl lobes` computes them: critical depth " + num(run.fd.critical_depth_m * 1e3) +
      " mm at " + num(run.fd.critical_chatter_Hz) + " Hz), their depth b read as " + o.depth +
      (o.depth_exponent > 0.0
           ? " = " + num(o.depth_reference) + "·(b/" + num(o.depth_reference) + ")^(1/(1 − " +
                 num(o.depth_exponent) + "))"
           : " = b") +
      "; the lines are drawn where the grid's values increase.");
  if (o.chatter.empty()) return;
  // Each grid point: its speed and depth values (last key fastest), the simulated verdict.
  std::vector<std::size_t> stride(spec.grid.size(), 1);
  for (std::size_t k = spec.grid.size() - 1; k-- > 0;)
    stride[k] = stride[k + 1] * spec.grid[k + 1].values.size();
  const std::size_t is = speed_x ? 1 : 0, id = 1 - is;
  Tally fd, sd;
  io::Table t{"Where the simulation and the lobes disagree",
              {"case", o.speed, o.depth, o.chatter, "frequency-domain limit",
               "semi-discretization limit", "simulated"},
              {}};
  for (std::size_t p = 0; p < chatter.size(); ++p) {
    if (!std::isfinite(chatter[p])) continue;
    const Value& vn = spec.grid[is].values[p / stride[is] % spec.grid[is].values.size()];
    const Value& vy = spec.grid[id].values[p / stride[id] % spec.grid[id].values.size()];
    const double n = number_of(vn), y = number_of(vy);
    const bool sim = chatter[p] > o.chatter_above;
    const double l_fd = as_depth_key(o, dynamics::envelope_depth(run.fd, n) * 1e3);
    const double l_sd = as_depth_key(o, at_speed(curves.chart, n));
    fd.add(sim, y, l_fd);
    sd.add(sim, y, l_sd);
    if ((std::isfinite(l_fd) && (y > l_fd) != sim) || (std::isfinite(l_sd) && (y > l_sd) != sim))
      t.rows.push_back({std::to_string(p * std::max<std::size_t>(1, spec.samples)), to_text(vn),
                        to_text(vy), num(chatter[p]), num(l_fd), num(l_sd),
                        sim ? "chatter" : "stable"});
  }
  fd.report("frequency domain", rep);
  sd.report("semi-discretization chart", rep);
  rep.notes.push_back("A grid point chatters in the simulation when " + o.chatter + " > " +
                      num(o.chatter_above) + " (the mean of its samples), by the lobes when " +
                      o.depth + " lies above the limit at its " + o.speed + ".");
  if (!t.rows.empty()) rep.tables.push_back(std::move(t));
}

}  // namespace lathectl::sweep
