// The feeds: each feed move cut into pieces where its engagement changes, each piece at the
// largest feed per revolution the scenario's limits allow.
#include "optimize/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "optimize/chatter.hpp"
#include "optimize/path.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

struct Span {  // a piece of a move as a range of samples
  std::size_t a = 0, b = 0;
  bool cut = false;
};

// The chatter limit is a lower bound on the feed (chatter.hpp: k_c = ∂Pz/∂s ∝ s^(y−1) falls as
// the feed rises). The smallest feed per revolution in [f, f_top] at which every sample of the
// span in cut is stable (k_c ≤ k_lim at its depth, speed and position): f itself when it is
// stable, nothing when f_top is not. The ratio k_c/k_lim of two samples does not depend on the
// feed (the same power of s), so the sample worst at f is worst at every feed: it alone is solved.
std::optional<double> stable_feed(const cutting::CuttingModel& cut, const Samples& s,
                                  const Span& sp, double f, double f_top) {
  std::size_t worst = sp.b;
  double r = 0.0;
  auto ratio = [&](std::size_t i, double feed) {
    return chip_stiffness(cut, {s.depth[i], feed, s.speed[i], s.strength[i], s.wear[i]})
               .k_N_per_m /
           s.kcrit[i];
  };
  for (std::size_t i = sp.a; i < sp.b; ++i) {
    if (!(s.depth[i] > 0.0) || !(s.kcrit[i] > 0.0)) continue;  // NaN: not in cut
    const double q = ratio(i, f);
    if (q > r) {
      r = q;
      worst = i;
    }
  }
  // Aimed a hair inside the boundary (k_c ≤ 0.999 k_lim): once the program is rewritten the
  // prediction's samples fall a little differently along the piece, and a feed solved exactly
  // on the boundary came out at margin 0.999999 there.
  constexpr double kStable = 0.999;
  if (worst == sp.b || r <= kStable) return f;
  if (ratio(worst, f_top) > kStable) return std::nullopt;
  double lo = f, hi = f_top;  // unstable at lo, stable at hi
  for (int k = 0; k < 50; ++k) {
    const double mid = 0.5 * (lo + hi);
    (ratio(worst, mid) > kStable ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> move_ranges(const Samples& s, std::size_t moves) {
  std::vector<std::pair<std::size_t, std::size_t>> r(moves, {0, 0});
  for (std::size_t i = 0; i < s.move.size();) {
    std::size_t j = i;
    while (j < s.move.size() && s.move[j] == s.move[i]) ++j;
    r[static_cast<std::size_t>(s.move[i])] = {i, j};
    i = j;
  }
  return r;
}

FeedLimits feed_limits(const systems::e_adaptive::Settings& e, const Options& opt) {
  const auto& c = e.rig.controller;
  FeedLimits l;
  l.param = opt.limit_fraction * c.load_limit;
  l.power_W = opt.limit_fraction * std::min(e.rig.spindle.max_power_W, c.cut_power_max_W);
  l.torque_N_m = opt.limit_fraction * e.rig.spindle.max_torque_N_m;
  l.feed_min = c.feed_min_mm_per_rev;
  l.feed_max = c.feed_max_mm_per_rev;
  l.air = opt.air_feed > 0.0 ? opt.air_feed : c.feed_max_mm_per_rev;
  return l;
}

// The largest feed per revolution in [feed_min, feed_max] that keeps the force parameter, the
// cutting power and the spindle torque within the limits at depth t, speed V, strength h, wear w,
// radius x; bisection (each quantity grows with the feed).
std::pair<double, std::string> largest_feed(const cutting::CuttingModel& cut,
                                            cutting::ForceParameter which, const FeedLimits& l,
                                            double t, double v, double h, double w, double x) {
  std::string why;
  auto ok = [&](double s) {
    const auto f = cut.forces({t, s, v, h, w});
    const double p = cut.power_W(f, v);
    why = cutting::force_parameter(which, f, p) > l.param ? "force"
          : p > l.power_W                                 ? "power"
          : f.Pz * (x + t) * 1e-3 > l.torque_N_m          ? "torque"
                                                          : "";
    return why.empty();
  };
  if (ok(l.feed_max)) return {l.feed_max, "feed_max"};
  if (!ok(l.feed_min)) return {l.feed_min, "feed_min (" + why + " above its limit)"};
  double lo = l.feed_min, hi = l.feed_max;
  std::string at_hi = why;
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (ok(mid)) {
      lo = mid;
    } else {
      hi = mid;
      at_hi = why;
    }
  }
  return {lo, at_hi};
}

namespace {

// The feed of a piece whose samples are `sp` (in cut or in air): the largest the limits allow at
// its deepest per-revolution engagement, at most the roughness feed when it is finishing, at
// least the chatter-stable feed when the scenario has modes.
struct FeedContext {
  const cutting::CuttingModel& cut;
  const systems::e_adaptive::Settings& e;
  const Options& opt;
  FeedLimits lim;
  double r_nose;  // the largest nose of the program's tools (tool_geometry)
  std::vector<double> rev_depth;
};
void span_feed(const FeedContext& ctx, const CanonMove& m, const std::string& finishing,
               const std::string& finishing_pass, const ToolSpec* spec, const Samples& s,
               const Span& sp, Piece& pc) {
  const auto& cut = ctx.cut;
  const auto& e = ctx.e;
  const auto& opt = ctx.opt;
  FeedLimits lim = ctx.lim;
  // The finish's corner radius: the tool's own nose (tool_geometry: the tool file's, the tool
  // table's D/2, the scenario's), the one the prediction cut with.
  const double r_nose = tool_geometry(opt, e, m.tool).nose_radius_mm;
  if (spec) {  // the insert's own feed range (air included)
    if (spec->feed_min_mm_per_rev > 0.0) lim.feed_min = spec->feed_min_mm_per_rev;
    if (spec->feed_max_mm_per_rev > 0.0) lim.feed_max = spec->feed_max_mm_per_rev;
    lim.feed_min = std::min(lim.feed_min, lim.feed_max);
    lim.air = std::min(lim.air, lim.feed_max);
  }
  const auto& rev_depth = ctx.rev_depth;
  double rpm_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = sp.a; i < sp.b; ++i) rpm_min = std::min(rpm_min, s.rpm[i]);
  double f_rev = lim.air;
  const double programmed_rev = m.per_rev ? m.feed : m.feed / std::max(rpm_min, 1e-9);
  if (sp.cut) {
    double t = 0.0, h = 0.0, w = 1.0, v = std::numeric_limits<double>::infinity(), x = 0.0;
    for (std::size_t i = sp.a; i < sp.b; ++i) {
      t = std::max(t, rev_depth[i]);
      h = std::max(h, s.strength[i]);
      w = std::max(w, s.wear[i]);
      x = std::max(x, s.x[i]);
      if (s.speed[i] > 0.0) v = std::min(v, s.speed[i]);
    }
    if (!std::isfinite(v)) v = 2.0 * std::numbers::pi * x * rpm_min / 1000.0;
    // A grooving or parting insert plunges its whole width into the part: that is the width of
    // cut of the law (the feed per revolution its chip thickness), not the nose's engagement.
    if (spec && spec->plunge() && t > 0.0) t = spec->insert_width_mm;
    if (t > 0.0 && v > 0.0) {
      auto [f, why] = largest_feed(cut, e.rig.force_parameter, lim, t, v, h, w, x);
      pc.limited_by = why;
      f_rev = f;
      const double f_limits = f;  // the largest feed force, power and torque allow
      if (t <= opt.finish_depth_mm || !finishing.empty()) {
        // finishing: Ra = f²/(32 r) at most the target
        const double ra =
            opt.finish_ra_um > 0.0 ? opt.finish_ra_um : cut.roughness_Ra_um(programmed_rev);
        // Never rougher than the program: --finish-ra-um may ask for a smoother surface, not a
        // coarser one (the roughness feed above the programmed one raised 0.06 to 0.29 mm/rev).
        const double f_ra = std::min(std::sqrt(ra * 1e-3 * 32.0 * r_nose), programmed_rev);
        if (f_ra < f_rev) {
          f_rev = std::max(f_ra, lim.feed_min);
          pc.limited_by = "roughness";
        }
      }
      if (!finishing.empty()) {
        // A finishing cut by its kind, not its depth (a deep fillet, a G64 corner that makes a
        // light pass look deep): never above the programmed feed, and no chatter raise.
        if (programmed_rev < f_rev) {
          f_rev = programmed_rev;
          pc.limited_by = "roughness";
        }
        pc.limited_by += " (finishing: " + finishing + ")";
      } else if (!s.kcrit.empty()) {  // the scenario has modes: the feed that keeps margin ≥ 1
        const auto fc = stable_feed(cut, s, sp, f_rev, std::max(f_limits, f_rev));
        if (!fc) {
          pc.limited_by += " + chatter: unstable at every feed within the limits";
        } else if (*fc > f_rev) {
          pc.limited_by = pc.limited_by == "roughness" ? "chatter (above the roughness feed)"
                                                       : "chatter";
          f_rev = *fc;
        }
      }
    } else {
      pc.limited_by = "air";
    }
  } else {
    pc.limited_by = "air";
  }
  if ((!finishing.empty() || !finishing_pass.empty()) && pc.limited_by == "air" &&
      programmed_rev < f_rev) {
    // A finishing pass's piece the stock model finds in air (a face, shoulder or chamfer it
    // does not know was left there) is not raised either.
    f_rev = programmed_rev;
    pc.limited_by =
        "air, not raised (finishing: " + (finishing.empty() ? finishing_pass : finishing) + ")";
  }
  if (m.per_rev) {
    pc.feed = f_rev;
  } else if (rpm_min > 0.0 && std::isfinite(rpm_min)) {
    pc.feed = f_rev * rpm_min;
  } else {
    pc.feed = m.feed;  // G94 with the spindle stopped: nothing to scale by
    pc.limited_by = "spindle stopped (kept)";
  }
}

// Per sample: in cut, or near enough that the last revolution's chip reaches into it (`reach`:
// the nose's width and a revolution at the air feed on either side of the material).
std::vector<char> near_material(const Samples& s, double reach) {
  const std::size_t n = s.depth.size();
  std::vector<char> near(n, 0);
  double last = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (s.depth[i] > 0.0) last = s.path_mm[i];
    near[i] = s.path_mm[i] - last <= reach;
  }
  double next = std::numeric_limits<double>::infinity();
  for (std::size_t i = n; i-- > 0;) {
    if (s.depth[i] > 0.0) next = s.path_mm[i];
    near[i] = near[i] || next - s.path_mm[i] <= reach;
  }
  return near;
}

// The largest nose among the tools the program's moves use (tool_geometry): the reach of
// near_material().
double program_nose_mm(const io::CanonProgram& prog, const systems::e_adaptive::Settings& e,
                       const Options& opt) {
  double r = 0.0;
  int last = -1;
  for (const CanonMove& m : prog.moves)
    if (m.tool != last) {
      last = m.tool;
      r = std::max(r, tool_geometry(opt, e, m.tool).nose_radius_mm);
    }
  return r > 0.0 ? r : e.rig.cutting.nose_radius_mm;
}

}  // namespace

Plan choose_feeds(const io::CanonProgram& prog, const Prediction& before,
                  const systems::e_adaptive::Settings& e, const Options& opt,
                  const MoveRoles& roles) {
  const Samples& s = before.s;
  const FeedLimits lim = feed_limits(e, opt);
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  const double r_nose = program_nose_mm(prog, e, opt);
  const FeedContext ctx{cut, e, opt, lim, r_nose, control::per_revolution_mean(s.depth, s.rpm, s.dt_s)};
  const auto& rev_depth = ctx.rev_depth;
  const std::vector<char> near = near_material(s, 2.0 * r_nose + lim.air + 0.5);
  const auto ranges = move_ranges(s, prog.moves.size());
  const double min_piece_mm = 3.0;
  Plan plan = programmed(prog);
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    const CanonMove& m = prog.moves[mi];
    auto& pieces = plan[mi];
    if (m.kind == CanonMove::Kind::Traverse) {
      pieces[0].limited_by = "rapid";
      continue;
    }
    if (m.synced || !roles.kept[mi].empty()) {
      pieces[0].limited_by = m.synced ? "threading (kept)" : roles.kept[mi];
      continue;
    }
    const auto [a, b] = ranges[mi];
    const double len = move_length(m);
    if (a == b || !(len > 0.0)) continue;
    // Spans: air / cut, cut spans split where the per-revolution depth leaves a band of ±30 %.
    std::vector<Span> spans;
    double lo = 0.0, hi = 0.0;
    for (std::size_t i = a; i < b; ++i) {
      const bool c = near[i] != 0;
      const double d = rev_depth[i];
      bool start = spans.empty() || spans.back().cut != c;
      if (!start && c && d > 0.0) {
        if (lo <= 0.0) {
          lo = hi = d;
        } else if (d > 1.3 * lo || d < hi / 1.3) {
          start = true;
        }
        lo = std::min(lo, d);
        hi = std::max(hi, d);
      }
      if (start) {
        spans.push_back({i, i + 1, c});
        lo = hi = c ? d : 0.0;
      } else {
        spans.back().b = i + 1;
      }
    }
    // Short spans join their neighbour (a cut span never becomes air).
    const double path0 = a > 0 ? s.path_mm[a - 1] : 0.0;
    // (a structured binding is not captured by a lambda before C++20's P1091 in clang 14)
    auto length = [&, first = a](const Span& sp) {
      return s.path_mm[sp.b - 1] - (sp.a > first ? s.path_mm[sp.a - 1] : path0);
    };
    for (std::size_t k = 0; k + 1 < spans.size();) {
      if (length(spans[k]) < min_piece_mm || length(spans[k + 1]) < min_piece_mm) {
        spans[k].b = spans[k + 1].b;
        spans[k].cut = spans[k].cut || spans[k + 1].cut;
        spans.erase(spans.begin() + static_cast<std::ptrdiff_t>(k) + 1);
      } else {
        ++k;
      }
    }
    pieces.clear();
    for (const auto& sp : spans) {
      Piece pc;
      pc.from = pieces.empty() ? 0.0 : pieces.back().to;
      pc.to = sp.b == b ? 1.0 : std::clamp((s.path_mm[sp.b - 1] - path0) / len, pc.from, 1.0);
      span_feed(ctx, m, roles.finishing[mi], roles.finishing_pass[mi], roles.spec[mi], s, sp, pc);
      pieces.push_back(pc);
    }
    if (pieces.empty()) pieces = programmed(prog)[mi];
    pieces.back().to = 1.0;
    // The per-revolution depth that decides a boundary trails the tool by a revolution and the
    // nose reaches r_ε ahead of it: the slower piece of each pair takes `lead` more of the path,
    // so the heavier engagement never starts at the faster feed.
    const double lead = (2.0 * tool_geometry(opt, e, m.tool).nose_radius_mm + lim.feed_max) / len;
    for (std::size_t k = 0; k + 1 < pieces.size(); ++k) {
      auto& p0 = pieces[k];
      auto& p1 = pieces[k + 1];
      const double at =
          p1.feed < p0.feed ? std::max(p0.from, p0.to - lead) : std::min(p1.to, p0.to + lead);
      p0.to = p1.from = at;
    }
    std::erase_if(pieces, [](const Piece& pc) { return !(pc.to > pc.from); });
    if (!pieces.empty()) {
      pieces.front().from = 0.0;
      pieces.back().to = 1.0;
    }
  }
  return plan;
}

void refeed(const io::CanonProgram& prog, Plan& plan, const Prediction& trial,
            const systems::e_adaptive::Settings& e, const Options& opt,
            const MoveRoles& roles) {
  const Samples& s = trial.s;
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  const FeedLimits lim = feed_limits(e, opt);
  const double r_nose = program_nose_mm(prog, e, opt);
  const FeedContext ctx{cut, e, opt, lim, r_nose, control::per_revolution_mean(s.depth, s.rpm, s.dt_s)};
  const std::vector<char> near = near_material(s, 2.0 * r_nose + lim.air + 0.5);
  // A piece's samples are contiguous: a blend arc's come just before the piece it counts to.
  for (std::size_t i = 0; i < s.move.size();) {
    std::size_t j = i;
    bool in_cut = false;
    for (; j < s.move.size() && s.move[j] == s.move[i] && s.piece[j] == s.piece[i]; ++j)
      if (near[j] != 0) in_cut = true;
    const auto mi = static_cast<std::size_t>(s.move[i]);
    const auto pi = static_cast<std::size_t>(s.piece[i]);
    const CanonMove& m = prog.moves[mi];
    if (m.kind != CanonMove::Kind::Traverse && !m.synced && roles.kept[mi].empty() &&
        pi < plan[mi].size())
      span_feed(ctx, m, roles.finishing[mi], roles.finishing_pass[mi], roles.spec[mi], s,
                Span{i, j, in_cut}, plan[mi][pi]);
    i = j;
  }
}

}  // namespace lathectl::optimize
