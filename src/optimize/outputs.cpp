// The output set of `lathectl optimize`: optimized.ngc, blocks.csv (one row per piece of each
// feed move), summary.json and report.html (io::render_html).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "optimize/path.hpp"
#include "optimize/plan.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;
using nlohmann::json;

std::string num(double v, int digits = 6) {
  std::string s;
  io::append_general(s, v, digits);
  return s;
}

// Per-revolution mean of the force parameter in feed moves (a rapid through material is
// reported on its own: no feed acts on it) and its peak by the rig's and the LinuxCNC plant's
// rule (control::PerRevolutionPeak): over the cuts in feed moves, each cut's first revolution
// left out. Time is the samples' own (the last step of a piece may be shorter than dt_s).
control::PerRevolutionRecord rev_param(const io::CanonProgram& prog, const Samples& s) {
  std::vector<double> f(s.param.size()), t(s.param.size());
  std::vector<unsigned char> cutting(s.param.size());
  double now = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const bool feed =
        prog.moves[static_cast<std::size_t>(s.move[i])].kind != CanonMove::Kind::Traverse;
    f[i] = feed ? s.param[i] : 0.0;
    cutting[i] = feed && s.depth[i] > 0.0 && s.feed_rev[i] > 0.0 ? 1 : 0;
    t[i] = now;
    now += s.dt[i];
  }
  return control::per_revolution_peak(t, f, s.rpm, cutting, s.dt_s);
}

struct PieceStats {
  double time = 0.0, sum = 0.0, peak = 0.0, depth = 0.0, power = 0.0, torque = 0.0, life = 0.0;
  // With [chatter]: the least margin and limit depth over the piece's samples in cut.
  double margin = std::numeric_limits<double>::infinity();
  double limit_depth = std::numeric_limits<double>::infinity();
};
// Stats of each piece of `plan` from samples of a run whose plan may differ: a sample belongs to
// the piece its share of the move lies in.
std::vector<std::vector<PieceStats>> stats(const io::CanonProgram& prog, const Plan& plan,
                                           const Samples& s, const std::vector<double>& rev) {
  std::vector<std::vector<PieceStats>> st(plan.size());
  for (std::size_t i = 0; i < plan.size(); ++i) st[i].resize(plan[i].size());
  const auto ranges = move_ranges(s, prog.moves.size());
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    const auto [a, b] = ranges[mi];
    if (a == b) continue;
    const double p0 = a > 0 ? s.path_mm[a - 1] : 0.0;
    const double len = std::max(move_length(prog.moves[mi]), 1e-12);
    std::size_t k = 0;
    for (std::size_t i = a; i < b; ++i) {
      const double u = (s.path_mm[i] - p0) / len;
      while (k + 1 < plan[mi].size() && u > plan[mi][k].to + 1e-9) ++k;
      auto& x = st[mi][k];
      x.time += s.dt[i];
      x.sum += s.param[i] * s.dt[i];
      x.peak = std::max(x.peak, rev[i]);
      x.depth = std::max(x.depth, s.depth[i]);
      x.power = std::max(x.power, s.power[i]);
      x.torque = std::max(x.torque, s.torque[i]);
      x.life += s.life_use[i];
      if (!s.margin.empty() && s.margin[i] >= 0.0) {  // NaN out of cut
        x.margin = std::min(x.margin, s.margin[i]);
        x.limit_depth = std::min(x.limit_depth, s.margin[i] * s.depth[i]);
      }
    }
  }
  return st;
}

// The review's picture of the part in the XZ plane (machine z across, radius up): the blank,
// the finished part the optimised program leaves (predicted), the program's path — rapids
// dashed, feed moves, and the moves of the lines counted as changed in red. Drawn from the
// moves' geometry (arcs in 5° steps), not the samples, so each series stays a few thousand
// points; a break (NaN) between moves that do not join.
io::Plot tool_path_picture(const io::CanonProgram& prog, const Result& r) {
  io::Plot pl{"Tool path: blank, path and finished part (changed lines in red)",
              "machine z [mm]", "radius x [mm]", {}, {}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  io::Series rapids{"rapids (G0)", {}, {}, "#9a9a9a", true, false};
  io::Series feeds{"feed moves", {}, {}, "#1f77b4", false, false};
  io::Series changed{"changed lines", {}, {}, "#d62728", false, false};
  for (const CanonMove& m : prog.moves) {
    const bool is_changed = m.kind != CanonMove::Kind::Traverse && m.line >= 1 &&
                            static_cast<std::size_t>(m.line) <= r.actions.size() &&
                            r.actions[static_cast<std::size_t>(m.line - 1)].changed;
    io::Series& sr = m.kind == CanonMove::Kind::Traverse ? rapids : is_changed ? changed : feeds;
    const auto [x0, z0] = point_at(m, 0.0);
    if (sr.x.empty() || sr.x.back() != z0 || sr.y.back() != x0) {
      if (!sr.x.empty()) {
        sr.x.push_back(nan);
        sr.y.push_back(nan);
      }
      sr.x.push_back(z0);
      sr.y.push_back(x0);
    }
    const double sweep = m.kind == CanonMove::Kind::Arc ? std::abs(arc_sweep(m)) : 0.0;
    const int steps =
        std::clamp(static_cast<int>(std::ceil(sweep / (5.0 * std::numbers::pi / 180.0))), 1, 72);
    for (int k = 1; k <= steps; ++k) {
      const auto [x, z] = point_at(m, static_cast<double>(k) / steps);
      sr.x.push_back(z);
      sr.y.push_back(x);
    }
  }
  pl.series.push_back({"blank", r.before.part_z, r.before.blank_r, "#c8b27a", false, false});
  pl.series.push_back(
      {"finished part (optimised, predicted)", r.after.part_z, r.after.part_r, "#333333", false,
       false});
  pl.series.push_back(std::move(rapids));
  pl.series.push_back(std::move(feeds));
  pl.series.push_back(std::move(changed));
  return pl;
}

// Chatter margin or limit depth for the table: empty without modes, "inf" where no lobe reaches.
std::string chatter_cell(bool chatter, double v) {
  return !chatter ? "" : std::isfinite(v) ? num(v, 4) : "inf";
}
// The least margin over the samples in cut of feed moves; +inf when every one is stable at any
// depth.
double margin_min(const io::CanonProgram& prog, const Samples& s) {
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.margin.size(); ++i)
    if (s.margin[i] >= 0.0 &&
        prog.moves[static_cast<std::size_t>(s.move[i])].kind != CanonMove::Kind::Traverse)
      m = std::min(m, s.margin[i]);
  return m;
}
nlohmann::json finite_or_null(bool chatter, double v) {
  return chatter && std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

const char* kind_name(CanonMove::Kind k) {
  return k == CanonMove::Kind::Traverse ? "G0" : k == CanonMove::Kind::Line ? "G1" : "arc";
}

}  // namespace

std::string blend_note(const Prediction& p) {
  return "LinuxCNC's G64 blend at the corner after line " + std::to_string(p.blend_inside_line) +
         " cuts " + num(p.blend_inside_max_mm, 2) +
         " mm inside the programmed contour, in material: the part is undersize there unless "
         "the program sets a tolerance (G64 P0.01) or exact path (G61).";
}

std::string rapid_what(const io::CanonProgram& prog, int line) {
  bool travel = false, other = false;
  for (const auto& m : prog.moves)
    if (m.line == line && m.kind == CanonMove::Kind::Traverse) (m.tool_change ? travel : other) = true;
  return travel && !other ? "LinuxCNC's travel to [EMCIO]TOOL_CHANGE_POSITION at the M6"
                          : "a rapid (G0)";
}

std::vector<std::string> warnings(const Program& p, const systems::e_adaptive::Settings& e,
                                  const Result& r) {
  const auto& prog = p.canon;
  const std::string unit = e.rig.force_parameter == cutting::ForceParameter::Power ? "W" : "N";
  std::vector<std::string> w;
  if (r.before.rapid_in_material_s > 0.0) {
    std::string what = rapid_what(prog, r.before.rapid_first_line);
    what[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(what[0])));
    w.push_back(what + " of line " + std::to_string(r.before.rapid_first_line) +
                " passes through material for " + num(r.before.rapid_in_material_s, 3) +
                " s, up to " + num(r.before.rapid_peak, 4) + " " + unit +
                ": feeds cannot help there; the program's path must change. The lines from it "
                "on keep their programmed feeds.");
  }
  // The optimised program's peak above the limit: only a line kept as written can do that.
  const auto rev = rev_param(prog, r.after.s);
  double peak = 0.0;
  int line = 0;
  for (std::size_t i = 0; i < rev.mean.size(); ++i)
    if (rev.counted[i] != 0 && rev.mean[i] > peak) {
      peak = rev.mean[i];
      line = prog.moves[static_cast<std::size_t>(r.after.s.move[i])].line;
    }
  if (peak > r.limit) {
    std::string why;
    if (line >= 1 && static_cast<std::size_t>(line) <= r.actions.size() &&
        r.actions[static_cast<std::size_t>(line - 1)].kind == LineAction::Kind::Keep)
      why = ", kept as written: " + r.actions[static_cast<std::size_t>(line - 1)].why;
    w.push_back("The predicted per-revolution peak " + num(peak, 4) + " " + unit +
                " exceeds the limit " + num(r.limit, 4) + " " + unit + " on line " +
                std::to_string(line) + why + ".");
  }
  if (r.chatter) {
    int below = 0;
    for (std::size_t mi = 0; mi < r.optimized.size(); ++mi)
      if (prog.moves[mi].kind != CanonMove::Kind::Traverse)
        for (const auto& pc : r.optimized[mi])
          below += pc.limited_by.find(" + chatter") != std::string::npos ? 1 : 0;
    if (below > 0)
      w.push_back(std::to_string(below) +
                  " pieces of the optimised program are predicted to chatter (margin below 1): "
                  "see the table of chatter margins.");
  }
  return w;
}

namespace {

// What the outputs compare: the per-revolution force of each run, each piece's stats in each run
// (by the optimised plan's pieces), the pieces below chatter margin 1.
struct Compared {
  std::string unit;  // of the force parameter: "W" or "N"
  control::PerRevolutionRecord rev0, rev1;
  std::vector<std::vector<PieceStats>> st0, st1;
  int below0 = 0, below1 = 0;
  double mm0 = 0.0, mm1 = 0.0;  // least chatter margin
};

Compared compare(const io::CanonProgram& prog, const Result& r,
                 const systems::e_adaptive::Settings& e) {
  Compared c;
  c.unit = e.rig.force_parameter == cutting::ForceParameter::Power ? "W" : "N";
  c.rev0 = rev_param(prog, r.before.s);
  c.rev1 = rev_param(prog, r.after.s);
  c.st0 = stats(prog, r.optimized, r.before.s, c.rev0.mean);
  c.st1 = stats(prog, r.optimized, r.after.s, c.rev1.mean);
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    if (prog.moves[mi].kind == CanonMove::Kind::Traverse) continue;
    for (std::size_t k = 0; k < r.optimized[mi].size(); ++k) {
      c.below0 += c.st0[mi][k].margin < 1.0;
      c.below1 += c.st1[mi][k].margin < 1.0;
    }
  }
  c.mm0 = margin_min(prog, r.before.s);
  c.mm1 = margin_min(prog, r.after.s);
  return c;
}

// blocks.csv: one row per piece of each feed move.
std::string blocks_csv(const io::CanonProgram& prog, const Result& r, const Compared& c) {
  const std::string& unit = c.unit;
  std::string csv =
      "line,out_line,move,piece,motion,x_start_mm,z_start_mm,x_end_mm,z_end_mm,length_mm,"
      "feed_mode,feed_programmed,feed_optimized,limited_by,depth_max_mm,time_original_s,"
      "time_optimized_s,force_mean_original_" +
      unit + ",force_peak_rev_original_" + unit + ",force_mean_optimized_" + unit +
      ",force_peak_rev_optimized_" + unit + ",power_max_W,torque_max_N_m,tool_life_use_optimized,chatter_limit_depth_original_mm,"
      "chatter_margin_original,chatter_limit_depth_optimized_mm,chatter_margin_optimized\n";
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    const CanonMove& m = prog.moves[mi];
    if (m.kind == CanonMove::Kind::Traverse) continue;
    const double len = move_length(m);
    for (std::size_t k = 0; k < r.optimized[mi].size(); ++k) {
      const Piece& pc = r.optimized[mi][k];
      const auto [xs, zs] = point_at(m, pc.from);
      const auto [xe, ze] = point_at(m, pc.to);
      const auto& a = c.st0[mi][k];
      const auto& b = c.st1[mi][k];
      csv += std::to_string(m.line) + "," + std::to_string(pc.out_line) + "," + std::to_string(mi) +
             "," + std::to_string(k + 1) + "," + kind_name(m.kind) + "," + num(xs) + "," + num(zs) +
             "," + num(xe) + "," + num(ze) + "," + num(len * (pc.to - pc.from)) + "," +
             (m.per_rev ? "G95" : "G94") + "," + num(m.feed) + "," + num(pc.feed) + ",\"" +
             pc.limited_by + "\"," + num(std::max(a.depth, b.depth), 4) + "," + num(a.time, 5) +
             "," + num(b.time, 5) + "," + num(a.time > 0 ? a.sum / a.time : 0.0) + "," +
             num(a.peak) + "," + num(b.time > 0 ? b.sum / b.time : 0.0) + "," + num(b.peak) + "," +
             num(b.power) + "," + num(b.torque) + "," + num(b.life) + "," +
             chatter_cell(r.chatter, a.limit_depth) + "," + chatter_cell(r.chatter, a.margin) +
             "," + chatter_cell(r.chatter, b.limit_depth) + "," +
             chatter_cell(r.chatter, b.margin) + "\n";
    }
  }
  return csv;
}

const VerifyRun* verify_run(const Verified* v, const char* name) {
  if (!v) return nullptr;
  for (const auto& x : v->runs)
    if (x.name == name) return &x;
  return nullptr;
}

// summary.json's cycle times and peaks: predicted, and as LinuxCNC ran them (--verify).
void summary_times(json& js, const Result& r, const Verified* v, const Compared& c) {
  const VerifyRun *vo = verify_run(v, "original"), *vp = verify_run(v, "optimized"),
                  *vo_on = verify_run(v, "original_online"),
                  *vp_on = verify_run(v, "optimized_online");
  js["predicted_cycle_time_original_s"] = r.before.cycle_time_s;
  js["predicted_cycle_time_optimized_s"] = r.after.cycle_time_s;
  js["predicted_accel_time_original_s"] = r.before.accel_time_s;
  js["predicted_accel_time_optimized_s"] = r.after.accel_time_s;
  js["predicted_force_peak_rev_original_N"] = c.rev0.peak;
  js["predicted_force_peak_rev_optimized_N"] = c.rev1.peak;
  js["cycle_time_original_s"] = vo ? vo->cycle_time_s : r.before.cycle_time_s;
  js["cycle_time_optimized_s"] = vp ? vp->cycle_time_s : r.after.cycle_time_s;
  js["force_peak_rev_original_N"] = vo ? vo->force_peak_rev : c.rev0.peak;
  js["force_peak_rev_optimized_N"] = vp ? vp->force_peak_rev : c.rev1.peak;
  js["prediction_error_pct"] = v ? json(v->prediction_error_pct) : json(nullptr);
  if (v) {
    js["prediction_error_line"] = v->prediction_error_line;
    js["prediction_lines_compared"] = v->lines_compared;
    js["cycle_time_original_online_s"] = vo_on->cycle_time_s;
    js["cycle_time_optimized_online_s"] = vp_on->cycle_time_s;
    js["force_peak_rev_original_online_N"] = vo_on->force_peak_rev;
    js["force_peak_rev_optimized_online_N"] = vp_on->force_peak_rev;
    for (const auto& x : v->runs) {
      js["verify"][x.name] = {{"finished", x.finished}, {"retried", x.retried},
                              {"cycle_time_s", x.cycle_time_s},
                              {"force_peak_rev_N", x.force_peak_rev},
                              {"rapid_in_material_s", x.rapid_in_material_s},
                              {"force_peak_in_rapid_N", x.rapid_peak}};
    }
  }
  js["verified"] = v != nullptr;
}

// summary.json.
json summary_json(const Program& p, const Result& r, const systems::e_adaptive::Settings& e,
                  const Options& opt, const std::string& scenario_file, const Verified* v,
                  const Compared& c) {
  json js;
  js["program"] = p.file;
  js["scenario"] = scenario_file;
  // The units optimized.ngc writes in (its F words, its pieces' X Z I K): the program's, G20 or
  // G21 where each move is; everything else here and in blocks.csv is in mm.
  bool mm = false, inch = false;
  for (const auto& m : p.canon.moves) (m.unit_mm > 1.0 + 1e-9 ? inch : mm) = true;
  js["program_units"] = inch && mm ? "mm and inch" : inch ? "inch" : "mm";
  js["machine_ini"] = opt.ini;
  js["force_parameter"] = c.unit == "W"                                          ? "power"
                          : e.rig.force_parameter == cutting::ForceParameter::Py ? "Py"
                                                                                 : "Pz";
  js["force_limit_N"] = r.limit;
  summary_times(js, r, v, c);
  js["blocks_changed"] = r.blocks_changed;
  js["splits_dropped"] = r.splits_dropped;
  // Chatter (scenario [chatter]): null without modes, or where no lobe reaches (stable at any
  // depth); the blocks are the rows of blocks.csv.
  js["chatter_margin_min_original"] = finite_or_null(r.chatter, c.mm0);
  js["chatter_margin_min_optimized"] = finite_or_null(r.chatter, c.mm1);
  js["chatter_blocks_below_1_original"] = r.chatter ? json(c.below0) : json(nullptr);
  js["chatter_blocks_below_1_optimized"] = r.chatter ? json(c.below1) : json(nullptr);
  js["tool_life_use_original"] = r.before.life_use;
  js["tool_life_use_optimized"] = r.after.life_use;
  js["predicted_rapid_in_material_s"] = r.before.rapid_in_material_s;
  js["predicted_force_peak_in_rapid_N"] = r.before.rapid_peak;
  js["predicted_rapid_in_material_first_line"] = r.before.rapid_first_line;
  js["predicted_blend_inside_max_mm"] = r.before.blend_inside_max_mm;
  js["predicted_blend_inside_line"] = r.before.blend_inside_line;
  const auto lim = feed_limits(e, opt);
  js["limits"] = {{"force", r.limit},
                  {"power_W", e.rig.spindle.max_power_W},
                  {"torque_N_m", e.rig.spindle.max_torque_N_m},
                  {"feed_min_mm_per_rev", lim.feed_min},
                  {"feed_max_mm_per_rev", lim.feed_max},
                  {"air_feed_mm_per_rev", lim.air},
                  {"limit_fraction", opt.limit_fraction},
                  {"finish_depth_mm", opt.finish_depth_mm},
                  {"finish_ra_um",
                   opt.finish_ra_um > 0.0 ? json(opt.finish_ra_um) : json("programmed feed's")}};
  json kept = json::array();
  for (std::size_t li = 0; li < r.actions.size(); ++li)
    if (r.actions[li].kind == LineAction::Kind::Keep)
      kept.push_back({{"line", li + 1}, {"why", r.actions[li].why}});
  js["lines_kept"] = kept;
  return js;
}

// report.html's metrics (the cycle times and peaks as summary.json has them) and its verdict:
// the warnings, what a programmer must see before anything else.
void report_metrics(io::Report& rep, const Program& p, const Result& r,
                    const systems::e_adaptive::Settings& e, const Verified* v, const json& js,
                    const Compared& c) {
  const std::string& unit = c.unit;
  auto m = [&](const std::string& k, double x, const std::string& u) {
    rep.metrics.emplace_back(k, num(x, 4) + " " + u);
  };
  m("cycle time, original", js["cycle_time_original_s"].get<double>(), "s");
  m("cycle time, optimised", js["cycle_time_optimized_s"].get<double>(), "s");
  m("force limit", r.limit, unit);
  m("per-revolution force peak, original", js["force_peak_rev_original_N"].get<double>(), unit);
  m("per-revolution force peak, optimised", js["force_peak_rev_optimized_N"].get<double>(), unit);
  if (v) {
    m("prediction error (largest per line)", v->prediction_error_pct, "% of the limit");
    m("cycle time with online control, original",
      verify_run(v, "original_online")->cycle_time_s, "s");
    m("cycle time with online control, optimised",
      verify_run(v, "optimized_online")->cycle_time_s, "s");
  }
  m("lines changed", r.blocks_changed, "");
  m("tool life used, original", r.before.life_use, "");
  m("tool life used, optimised", r.after.life_use, "");
  if (r.chatter) {
    m("least chatter margin, original", c.mm0, "");
    m("least chatter margin, optimised", c.mm1, "");
    m("pieces below margin 1, original", c.below0, "");
    m("pieces below margin 1, optimised", c.below1, "");
  }
  const std::vector<std::string> warnings = optimize::warnings(p, e, r);
  for (const auto& w : warnings) rep.verdict += (rep.verdict.empty() ? "" : " ") + w;
  rep.verdict_ok = warnings.empty();
  if (!warnings.empty()) rep.verdict_table.title = "Warnings";
  if (r.before.blend_inside_max_mm > 0.01)
    rep.notes.push_back(blend_note(r.before));
  if (r.splits_dropped)
    rep.notes.push_back(
        "The pieces of split lines did not follow the original path when "
        "interpreted (modes such as G91, G7 or offsets): each line got one F.");
}

std::vector<double> decimate(const std::vector<double>& x, std::size_t every) {
  std::vector<double> o;
  for (std::size_t i = 0; i < x.size(); i += every) o.push_back(x[i]);
  return o;
}

// report.html's plots: the tool path, force and feed along the path, LinuxCNC's force over time.
void report_plots(io::Report& rep, const io::CanonProgram& prog, const Result& r,
                  const Verified* v, const Compared& c) {
  const std::string& unit = c.unit;
  const std::size_t e0 = std::max<std::size_t>(1, r.before.s.path_mm.size() / 20000);
  const std::size_t e1 = std::max<std::size_t>(1, r.after.s.path_mm.size() / 20000);
  io::Plot pf{"Predicted force along the path (per-revolution mean)",
              "path [mm]",
              "force parameter [" + unit + "]",
              {},
              {}};
  pf.series.push_back(
      {"original", decimate(r.before.s.path_mm, e0), decimate(c.rev0.mean, e0), "", false, false});
  pf.series.push_back(
      {"optimised", decimate(r.after.s.path_mm, e1), decimate(c.rev1.mean, e1), "", false, false});
  pf.series.push_back({"limit",
                       {0.0, r.after.s.path_mm.empty() ? 1.0 : r.after.s.path_mm.back()},
                       {r.limit, r.limit},
                       "",
                       true,
                       false});
  // Feed moves only: a rapid's "feed per revolution" (several mm) would set the scale.
  auto feed_only = [&](const Samples& s, std::size_t every) {
    std::pair<std::vector<double>, std::vector<double>> xy;
    for (std::size_t i = 0; i < s.path_mm.size(); i += every)
      if (prog.moves[static_cast<std::size_t>(s.move[i])].kind != CanonMove::Kind::Traverse) {
        xy.first.push_back(s.path_mm[i]);
        xy.second.push_back(s.feed_rev[i]);
      }
    return xy;
  };
  io::Plot pfeed{"Feed per revolution along the path (feed moves)", "path [mm]", "feed [mm/rev]",
                 {}, {}};
  auto [fx0, fy0] = feed_only(r.before.s, e0);
  auto [fx1, fy1] = feed_only(r.after.s, e1);
  pfeed.series.push_back({"original", std::move(fx0), std::move(fy0), "", false, false});
  pfeed.series.push_back({"optimised", std::move(fx1), std::move(fy1), "", false, false});
  rep.plots = {tool_path_picture(prog, r), pf, pfeed};
  if (v) {
    io::Plot pv{"LinuxCNC: force over time (per-revolution mean, true value)",
                "time [s]",
                "force parameter [" + unit + "]",
                {},
                {}};
    for (const auto& x : v->runs) {
      const std::size_t k = std::max<std::size_t>(1, x.t.size() / 20000);
      pv.series.push_back({x.name, decimate(x.t, k), decimate(x.force_rev, k), "", false, false});
    }
    rep.plots.push_back(pv);
  }
}

// The review: every line counted as changed (the same lines as "lines changed"), its
// original and new feed, what kind of cut it is, the limit that decided and the predicted
// per-revolution peak; then the lines kept as written and why.
void report_lines(io::Report& rep, const io::CanonProgram& prog, const Result& r,
                  const Compared& c) {
  io::Table tb{"Lines changed (" + std::to_string(r.blocks_changed) + ")",
               {"line", "action", "cut", "F original", "F optimised", "limited by",
                "peak per rev. [" + c.unit + "]", "% of limit"},
               {}};
  io::Table tk{"Lines kept as written", {"line", "why"}, {}};
  for (std::size_t li = 0; li < r.actions.size(); ++li) {
    const auto k = r.actions[li].kind;
    if (k == LineAction::Kind::Keep && tk.rows.size() < 200)
      tk.rows.push_back({std::to_string(li + 1), r.actions[li].why});
    if (!r.actions[li].changed || tb.rows.size() >= 500) continue;
    std::string feeds, why, f0;
    double peak = 0.0;
    bool finishing = false, all_air = true;
    for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
      if (prog.moves[mi].line != static_cast<int>(li + 1) ||
          prog.moves[mi].kind == CanonMove::Kind::Traverse)
        continue;
      const std::string orig = num(prog.moves[mi].feed, 4);
      if (f0.empty()) f0 = orig;
      else if (f0.find(orig) == std::string::npos && f0.size() < 60) f0 += " " + orig;
      for (std::size_t pk = 0; pk < r.optimized[mi].size(); ++pk) {
        const auto& pc = r.optimized[mi][pk];
        if (feeds.size() < 80) feeds += (feeds.empty() ? "" : " ") + num(pc.feed, 4);
        if (why.find(pc.limited_by) == std::string::npos && why.size() < 80)
          why += (why.empty() ? "" : ", ") + pc.limited_by;
        finishing = finishing || pc.limited_by.find("roughness") != std::string::npos;
        all_air = all_air && pc.limited_by == "air";
        peak = std::max(peak, c.st1[mi][pk].peak);
      }
    }
    const char* names[] = {"", "kept", "F changed", "split", "cycle expanded"};
    tb.rows.push_back({std::to_string(li + 1), names[static_cast<int>(k)],
                       all_air ? "air" : finishing ? "finishing" : "roughing", f0,
                       feeds.size() >= 80 ? feeds + " …" : feeds, why, num(peak, 4),
                       num(100.0 * peak / r.limit, 3)});
  }
  rep.tables.push_back(tb);
  if (!tk.rows.empty()) rep.tables.push_back(tk);
}

// The pieces whose chatter margin is below 1, original or optimised.
io::Table chatter_table(const io::CanonProgram& prog, const Result& r, const Compared& c) {
  io::Table tc{"Chatter margin below 1 (limit depth / depth; lobes of the modes at the piece)",
               {"line", "piece", "depth [mm]", "feed, original", "margin, original",
                "feed, optimised", "margin, optimised", "limited by"},
               {}};
  for (std::size_t mi = 0; mi < prog.moves.size() && tc.rows.size() < 200; ++mi) {
    if (prog.moves[mi].kind == CanonMove::Kind::Traverse) continue;
    for (std::size_t k = 0; k < r.optimized[mi].size(); ++k) {
      const auto &a = c.st0[mi][k], &b = c.st1[mi][k];
      if (!(a.margin < 1.0 || b.margin < 1.0)) continue;
      const Piece& pc = r.optimized[mi][k];
      tc.rows.push_back({std::to_string(prog.moves[mi].line), std::to_string(k + 1),
                         num(std::max(a.depth, b.depth), 4), num(prog.moves[mi].feed, 4),
                         chatter_cell(true, a.margin), num(pc.feed, 4),
                         chatter_cell(true, b.margin), pc.limited_by});
    }
  }
  if (tc.rows.empty()) tc.rows.push_back({"—", "", "", "", "", "", "", "every piece ≥ 1"});
  return tc;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> output_files(
    const Program& p, const Result& r, const systems::e_adaptive::Settings& e, const Options& opt,
    const std::string& scenario_file, const Verified* v) {
  const auto& prog = p.canon;
  const Compared c = compare(prog, r, e);
  const json js = summary_json(p, r, e, opt, scenario_file, v, c);
  io::Report rep;
  rep.title = "Feed optimisation of " + p.file;
  rep.subtitle = "scenario " + scenario_file + " (system E)";
  rep.description =
      "The program as LinuxCNC's interpreter (rs274) runs it, predicted on the scenario's blank "
      "by the cutting process of the LinuxCNC plant (cutting::LathePlant) at the servo period, and "
      "the same program with the largest feed per piece that keeps force, power and torque "
      "within the limits. " +
      std::string(v ? "Verified in LinuxCNC's simulated lathe (scripts/linuxcnc-sim)."
                    : "Not verified in LinuxCNC (--verify).");
  report_metrics(rep, p, r, e, v, js, c);
  report_plots(rep, prog, r, v, c);
  report_lines(rep, prog, r, c);
  if (r.chatter) rep.tables.push_back(chatter_table(prog, r, c));
  rep.doc_page = "optimize.md";
  return {{"optimized.ngc", r.ngc},
          {"blocks.csv", blocks_csv(prog, r, c)},
          {"summary.json", js.dump(2) + "\n"},
          {"report.html", io::render_html(rep)}};
}

}  // namespace lathectl::optimize
