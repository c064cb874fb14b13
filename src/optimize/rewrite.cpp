// optimized.ngc: the program's lines with the chosen feeds — an F word per line, a line split
// into pieces, or a cycle line expanded into its moves — checked by interpreting it again.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <string>

#include "lathectl/io/errors.hpp"
#include "optimize/chatter.hpp"
#include "optimize/path.hpp"
#include "optimize/plan.hpp"
#include "optimize/text.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;
using Kind = LineAction::Kind;

std::string number(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
// A feed [mm/rev, mm/min] as the move's program writes it: under G20 in in/rev (5 decimals) or
// in/min (2), else mm/rev (4) or mm/min (1).
bool inch(const CanonMove& m) { return m.unit_mm > 1.0 + 1e-9; }
std::string feed_text(const CanonMove& m, double f) {
  return number(f / m.unit_mm, (m.per_rev ? 4 : 1) + (inch(m) ? 1 : 0));
}
// A length [mm] in the move's program units: 4 decimals, 5 in inches (rs274 prints 4 of either,
// so the point written is the one it read, to its rounding).
std::string length_text(const CanonMove& m, double v) {
  return number(v / m.unit_mm, inch(m) ? 5 : 4);
}

// The line's text inside a comment: parentheses would end it early.
std::string commented(const std::string& l) {
  std::string o;
  for (char c : l) o += c == '(' ? '[' : c == ')' ? ']' : c;
  return o;
}

// Words a split line may hold: one straight or arc move, its end, centre and feed.
bool simple_move_line(const std::string& l) {
  for (const auto& w : words(l)) {
    if (w.letter == 'G') {
      if (w.value != "0" && w.value != "1" && w.value != "2" && w.value != "3" && w.value != "01" &&
          w.value != "02" && w.value != "03" && w.value != "00")
        return false;
    } else if (std::string("XZIKRFN").find(w.letter) == std::string::npos) {
      return false;
    }
  }
  return true;
}
// A canned turning cycle (G70/G71/G72 and their .1/.2) and its own words only.
bool cycle_line(const std::string& l) {
  bool cycle = false;
  for (const auto& w : words(l)) {
    if (w.letter == 'G') {
      const std::string v = w.value;
      if (v.rfind("70", 0) == 0 || v.rfind("71", 0) == 0 || v.rfind("72", 0) == 0)
        cycle = true;
      else
        return false;
    } else if (std::string("XZQDIKRPEFN").find(w.letter) == std::string::npos) {
      return false;
    }
  }
  return cycle;
}

// A G70 finishing cycle on the line.
bool finishing_cycle(const std::string& l) {
  for (const auto& w : words(l))
    if (w.letter == 'G' && (w.value == "70" || w.value == "70.0")) return true;
  return false;
}

std::string move_text(const CanonMove& m, double from, double to, double feed) {
  const auto [xs, zs] = point_at(m, from);
  const auto [xe, ze] = point_at(m, to);
  const std::string end = " X" + length_text(m, xe) + " Z" + length_text(m, ze);
  if (m.kind == CanonMove::Kind::Traverse) return "G0" + end;
  std::string t = m.kind == CanonMove::Kind::Line ? "G1" : (m.rotation < 0 ? "G2" : "G3");
  t += end;
  if (m.kind == CanonMove::Kind::Arc)
    t += " I" + length_text(m, m.xc - xs) + " K" + length_text(m, m.zc - zs);
  return t + " F" + feed_text(m, feed);
}

// Does `opt` run along `orig`? Every move of orig, in order, by the same kind of moves whose
// ends lie on it (the pieces of a split), zero-length moves left out.
bool same_path(const io::CanonProgram& orig, const io::CanonProgram& opt) {
  auto real = [](const io::CanonProgram& p) {
    std::vector<const CanonMove*> v;
    for (const auto& m : p.moves)
      if (move_length(m) > 1e-6) v.push_back(&m);
    return v;
  };
  const auto a = real(orig), b = real(opt);
  // mm: the program's 4 decimals, the interpreter's 4 (of an inch, 2.54 µm, under G20)
  const auto tol = [](const CanonMove& m) { return inch(m) ? 4e-3 : 2e-3; };
  std::size_t j = 0;
  for (const CanonMove* o : a) {
    for (;;) {
      if (j >= b.size()) return false;
      const CanonMove& m = *b[j++];
      const double kTol = tol(*o);
      if ((m.kind == CanonMove::Kind::Traverse) != (o->kind == CanonMove::Kind::Traverse))
        return false;
      if (o->kind == CanonMove::Kind::Arc) {
        const double r = std::hypot(o->x0 - o->xc, o->z0 - o->zc);
        if (std::abs(std::hypot(m.x1 - o->xc, m.z1 - o->zc) - r) > kTol) return false;
      } else {
        const double lx = o->x1 - o->x0, lz = o->z1 - o->z0;
        const double cross = ((m.x1 - o->x0) * lz - (m.z1 - o->z0) * lx) / std::hypot(lx, lz);
        if (std::abs(cross) > kTol) return false;
      }
      if (std::hypot(m.x1 - o->x1, m.z1 - o->z1) <= kTol) break;
      if (o->kind == CanonMove::Kind::Traverse) return false;
    }
  }
  return j == b.size();
}

bool differs(double a, double b) { return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b)); }

// One program line as write_program sees it: its moves and feed moves, whether it has an F word.
struct LineView {
  const std::string& text;
  int line;
  const std::vector<std::size_t>& mv;
  const CanonMove* first_feed = nullptr;
  const CanonMove* last_feed = nullptr;  // its feed is the original's modal F after the line
  bool has_f = false;
};

// Writes optimized.ngc's lines, one program line at a time by its action. The modal F of
// optimized.ngc may differ from the original's here (out_delta): a line that relies on the modal
// feed then needs its own F word.
struct ProgramWriter {
  const Program& p;
  Plan& plan;
  std::vector<std::string>& out;
  bool out_delta = false;

  int here() const { return static_cast<int>(out.size() + 1); }
  void set_lines(const LineView& l, int at) {
    for (auto mi : l.mv)
      for (auto& pc : plan[mi]) pc.out_line = at;
  }
  void none(const LineView& l) {
    set_lines(l, here());
    out.push_back(l.text);
    if (l.has_f) out_delta = false;  // sets the same modal F in both
  }
  void keep(const LineView& l) {
    // A thread's pitch is its own (G33 K, G76 P): it needs no feed restored.
    if (out_delta && l.first_feed && !l.has_f && !l.first_feed->synced) {
      out.push_back("F" + feed_text(*l.first_feed, l.first_feed->feed) +
                    " (lathectl: the programmed feed of the kept line " + std::to_string(l.line) +
                    ")");
      out_delta = false;
    }
    if (l.has_f) out_delta = false;
    set_lines(l, here());
    out.push_back(l.text);
  }
  void feed(const LineView& l) {
    std::size_t fi = l.mv.front();
    for (auto mi : l.mv)
      if (p.canon.moves[mi].kind != CanonMove::Kind::Traverse) {
        fi = mi;
        break;
      }
    const double f = plan[fi].front().feed;
    set_lines(l, here());
    bool same = true;  // every feed move of the line at its programmed feed
    for (auto mi : l.mv)
      if (p.canon.moves[mi].kind != CanonMove::Kind::Traverse)
        same = same && !differs(f, p.canon.moves[mi].feed);
    if (same && (l.has_f || !out_delta)) {  // nothing to change: the line as written
      out.push_back(l.text);
      out_delta = false;
      return;
    }
    out.push_back(with_feed(l.text, feed_text(*l.first_feed, f)).value_or(l.text));
    out_delta = differs(f, l.last_feed->feed);
  }
  void split(const LineView& l) {
    const std::size_t mi = l.mv.front();
    const CanonMove& m = p.canon.moves[mi];
    auto& pcs = plan[mi];
    const std::size_t n = pcs.size();
    for (std::size_t k = 0; k + 1 < n; ++k) {
      pcs[k].out_line = here();
      out.push_back(move_text(m, pcs[k].from, pcs[k].to, pcs[k].feed) + " (lathectl: line " +
                    std::to_string(l.line) + ", piece " + std::to_string(k + 1) + " of " +
                    std::to_string(n) + ")");
    }
    pcs.back().out_line = here();
    if (m.kind == CanonMove::Kind::Line) {
      out.push_back(with_feed(l.text, feed_text(m, pcs.back().feed)).value_or(l.text));
    } else {  // an arc's centre words are relative to its start: the last piece in full
      out.push_back(move_text(m, pcs.back().from, 1.0, pcs.back().feed) + " (lathectl: line " +
                    std::to_string(l.line) + ", piece " + std::to_string(n) + " of " +
                    std::to_string(n) + ": " + commented(l.text) + ")");
    }
    out_delta = differs(pcs.back().feed, m.feed);
  }
  void expand(const LineView& l) {
    out.push_back("(lathectl: line " + std::to_string(l.line) + " expanded into its " +
                  std::to_string(l.mv.size()) + " moves: " + commented(l.text) + ")");
    for (auto mi : l.mv) {
      const CanonMove& m = p.canon.moves[mi];
      if (move_length(m) <= 1e-6) {
        for (auto& pc : plan[mi]) pc.out_line = here();
        continue;
      }
      for (auto& pc : plan[mi]) {
        pc.out_line = here();
        out.push_back(move_text(m, pc.from, pc.to, pc.feed));
        if (m.kind != CanonMove::Kind::Traverse) out_delta = differs(pc.feed, m.feed);
      }
    }
  }
};

}  // namespace

// The text of optimized.ngc for these actions; fills each piece's output line.
std::string write_program(const Program& p, const std::vector<LineAction>& act, Plan& plan,
                          const std::vector<std::vector<std::size_t>>& line_moves,
                          std::vector<std::string>& out) {
  out.clear();
  ProgramWriter w{p, plan, out, false};
  for (std::size_t li = 0; li < p.lines.size(); ++li) {
    LineView l{p.lines[li], static_cast<int>(li + 1), line_moves[li], nullptr, nullptr, false};
    for (auto mi : l.mv)
      if (p.canon.moves[mi].kind != CanonMove::Kind::Traverse) {
        if (!l.first_feed) l.first_feed = &p.canon.moves[mi];
        l.last_feed = &p.canon.moves[mi];
      }
    const auto ws = words(l.text);
    l.has_f = std::any_of(ws.begin(), ws.end(), [](const Word& wd) { return wd.letter == 'F'; });
    switch (act[li].kind) {
      case Kind::None: w.none(l); break;
      case Kind::Keep: w.keep(l); break;
      case Kind::Feed: w.feed(l); break;
      case Kind::Split: w.split(l); break;
      case Kind::Expand: w.expand(l); break;
    }
  }
  std::string ngc;
  for (const auto& l : out) ngc += l + "\n";
  return ngc;
}

namespace {

// The moves of each program line (line_moves) and the roles of the feed moves: kept as written
// (marked, another tool, a threading tool's move), finishing (compensated, marked, G70).
MoveRoles move_roles(const Program& p, const Options& opt,
                     std::vector<std::vector<std::size_t>>& line_moves) {
  const auto& moves = p.canon.moves;
  line_moves.assign(p.lines.size(), {});
  MoveRoles roles;
  auto& kept = roles.kept;
  kept.resize(moves.size());
  roles.finishing.resize(moves.size());
  roles.spec.assign(moves.size(), nullptr);
  roles.finishing_pass.resize(moves.size());
  // The tools the scenario's [tool] describes: --tools, else the tool of the first feed move.
  std::vector<int> tools = opt.tools;
  for (const auto& m : moves)
    if (tools.empty() && m.kind != CanonMove::Kind::Traverse) tools.push_back(m.tool);
  std::string tool_list;
  for (int t : tools) tool_list += (tool_list.empty() ? "T" : ", T") + std::to_string(t);
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const int l = moves[i].line;
    const std::string* text =
        l >= 1 && static_cast<std::size_t>(l) <= p.lines.size() ? &p.lines[static_cast<std::size_t>(l - 1)]
                                                                  : nullptr;
    if (text) line_moves[static_cast<std::size_t>(l - 1)].push_back(i);
    if (moves[i].kind == CanonMove::Kind::Traverse) continue;
    const ToolSpec* spec = find_tool(opt.tool_specs, moves[i].tool);
    roles.spec[i] = spec;
    if (text && keep_marked(*text))
      kept[i] = "marked (lathectl:keep)";
    else if (!spec && std::find(tools.begin(), tools.end(), moves[i].tool) == tools.end())
      kept[i] = "tool T" + std::to_string(moves[i].tool) + " is not the scenario's [tool] (" +
                tool_list + "; --tools) nor in a --tool-file: its feed is kept";
    else if (spec && spec->kind == ToolSpec::Kind::Threading && !moves[i].synced)
      kept[i] = "a move of threading tool T" + std::to_string(moves[i].tool) + ": kept";
    if (moves[i].compensated)
      roles.finishing[i] = "cutter compensation";
    else if (text && finish_marked(*text))
      roles.finishing[i] = "marked (lathectl:finish)";
    else if (text && finishing_cycle(*text))
      roles.finishing[i] = "G70 finishing cycle";
  }
  return roles;
}

// A finishing pass that looks deep: a run of feed moves between rapids most of whose cut is at
// most the finish depth is a finishing pass, though corners left by the roughing (a fillet
// under the last pass) or a G64 blend arc make a few of its pieces deeper. Each piece would
// otherwise be judged by its deepest spot and the whole contour raised to a roughing feed.
void finishing_passes(const std::vector<CanonMove>& moves, const Samples& s, const Options& opt,
                      MoveRoles& roles) {
  std::vector<std::vector<std::pair<double, double>>> depth_len(moves.size());  // depth, length
  for (std::size_t i = 1; i < s.move.size(); ++i)
    if (s.depth[i] > 0.0)
      depth_len[static_cast<std::size_t>(s.move[i])].push_back(
          {s.depth[i], s.path_mm[i] - s.path_mm[i - 1]});
  for (std::size_t a = 0; a < moves.size();) {
    std::size_t b = a;
    while (b < moves.size() && moves[b].kind != CanonMove::Kind::Traverse) ++b;
    std::vector<std::pair<double, double>> in_cut;
    double total = 0.0, deepest = 0.0;
    for (std::size_t i = a; i < b; ++i)
      for (const auto& dl : depth_len[i]) {
        in_cut.push_back(dl);
        total += dl.second;
        deepest = std::max(deepest, dl.first);
      }
    if (total > 0.0) {
      std::sort(in_cut.begin(), in_cut.end());
      double acc = 0.0, median = 0.0;
      for (const auto& [d, l] : in_cut) {
        acc += l;
        median = d;
        if (acc >= 0.5 * total) break;
      }
      const std::string why =
          "the pass is " + number(median, 2) + " mm deep along half its cut or more";
      for (std::size_t i = a; i < b && median <= opt.finish_depth_mm; ++i) {
        roles.finishing_pass[i] = why;
        // Deeper than the finish depth somewhere: by its depth alone a piece would be roughing.
        if (deepest > opt.finish_depth_mm && roles.finishing[i].empty()) roles.finishing[i] = why;
      }
    }
    a = std::max(b, a + 1);
  }
}

// A rapid through material: LinuxCNC would drive the tool into the blank at rapid speed. It
// is an error unless allowed; allowed, the moves after it keep their feeds, because the stock
// model has the rapid's track removed and would take the next cut for air.
void keep_after_rapid(const Program& p, const Prediction& before, const Options& opt,
                      std::vector<std::string>& kept) {
  const auto& moves = p.canon.moves;
  const Samples& s = before.s;
  std::size_t first = moves.size();
  for (std::size_t i = 0; i < s.move.size() && first == moves.size(); ++i) {
    const auto mi = static_cast<std::size_t>(s.move[i]);
    if (moves[mi].kind == CanonMove::Kind::Traverse && s.param[i] > 0.0) first = mi;
  }
  if (!opt.allow_rapid_in_material)
    throw io::InputError(io::located(
        p.file, before.rapid_first_line, 0,
        rapid_what(p.canon, before.rapid_first_line) + " drives the tool through the blank (" +
            number(before.rapid_in_material_s, 3) + " s in material, the force parameter up to " +
            number(before.rapid_peak, 0) +
            " predicted): the path must change (--allow-rapid-in-material to optimise the "
            "lines before it anyway)"));
  const std::string why = "after the rapid through material of line " +
                          std::to_string(before.rapid_first_line) + " (kept)";
  for (std::size_t i = first; i < moves.size(); ++i)
    if (kept[i].empty()) kept[i] = why;
}

// How one line takes the chosen feeds: kept as written (every move kept, threading, G94 and G95
// mixed, an F that is an expression), split into pieces, a cycle expanded into its moves, or one
// F (the least of its pieces', with that piece's reason); r.optimized gets the line's pieces.
void act_on_line(const Program& p, std::size_t li, const std::vector<std::size_t>& mv,
                 const MoveRoles& roles, const Plan& chosen, bool allow_split, Result& r) {
  const auto& moves = p.canon.moves;
  std::vector<std::size_t> feeds;
  bool synced = false, comp = false, mixed = false;
  for (auto mi : mv) {
    if (moves[mi].kind == CanonMove::Kind::Traverse) continue;
    feeds.push_back(mi);
    synced = synced || moves[mi].synced;
    comp = comp || moves[mi].compensated;
    mixed = mixed || moves[mi].per_rev != moves[feeds.front()].per_rev;
  }
  if (feeds.empty()) return;
  const auto& kept = roles.kept;
  auto& a = r.actions[li];
  const std::string& text = p.lines[li];
  const bool all_kept = std::all_of(feeds.begin(), feeds.end(),
                                    [&](std::size_t mi) { return !kept[mi].empty(); });
  if (all_kept || synced || mixed || !with_feed(text, "1")) {
    a = {Kind::Keep, all_kept ? kept[feeds.front()]
                     : synced ? "threading"
                     : mixed  ? "G94 and G95 moves on one line"
                              : "its F word is an expression"};
    return;
  }
  double fmin = 1e300, fmax = 0.0;
  for (auto mi : feeds)
    for (const auto& pc : chosen[mi]) {
      fmin = std::min(fmin, pc.feed);
      fmax = std::max(fmax, pc.feed);
    }
  const bool contiguous = mv.back() - mv.front() + 1 == mv.size();
  if (allow_split && fmax > 1.03 * fmin && !comp && contiguous && mv.size() == 1 &&
      simple_move_line(text)) {
    a.kind = Kind::Split;
    r.optimized[mv.front()] = chosen[mv.front()];
  } else if (allow_split && fmax > 1.03 * fmin && !comp && contiguous && mv.size() > 1 &&
             cycle_line(text)) {
    a.kind = Kind::Expand;
    for (auto mi : mv) r.optimized[mi] = chosen[mi];
    for (auto mi : mv)
      if (moves[mi].kind == CanonMove::Kind::Traverse) r.optimized[mi] = r.original[mi];
  } else {
    a.kind = Kind::Feed;
    for (auto mi : mv)
      if (moves[mi].kind != CanonMove::Kind::Traverse)
        r.optimized[mi] = {{0.0, 1.0, fmin, chosen[feeds.front()].front().limited_by, 0}};
    // the limiting piece's reason
    for (auto mi : feeds)
      for (const auto& pc : chosen[mi])
        if (pc.feed == fmin)
          for (auto mj : feeds) r.optimized[mj].front().limited_by = pc.limited_by;
  }
}

// The actions and optimized.ngc: with split lines first; if the program so written does not
// follow the original path, once more with one F per line.
void write_actions(const Program& p, const std::vector<std::vector<std::size_t>>& line_moves,
                   const MoveRoles& roles, const Plan& chosen, const Options& opt, Result& r) {
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool allow_split = attempt == 0;
    r.actions.assign(p.lines.size(), {});
    r.optimized = r.original;
    for (std::size_t li = 0; li < p.lines.size(); ++li)
      act_on_line(p, li, line_moves[li], roles, chosen, allow_split, r);
    std::vector<std::string> out_lines;
    r.ngc = write_program(p, r.actions, r.optimized, line_moves, out_lines);
    // The inserted pieces and a cycle's moves are written in radius and absolute: under G7 (or
    // G91, offsets) they leave the path, and an arc among them may not even be one for the
    // interpreter (a G71 cycle in diameter mode: "radius to end of arc differs from radius to
    // start"). Either way the program with one F per line is the one to write.
    bool follows = false;
    try {
      follows = same_path(p.canon, interpret(out_lines, p.file + " (optimised)", opt));
    } catch (const io::InputError&) {
      if (!allow_split) throw;
    }
    if (follows) return;
    if (!allow_split)
      throw std::runtime_error(p.file +
                               ": the optimised program leaves the original path "
                               "(lathectl optimize's fault: please report it)");
    r.splits_dropped = true;
  }
}

// The lines changed: split or expanded, or given an F other than the programmed one.
void count_changed(const Program& p, const std::vector<std::vector<std::size_t>>& line_moves,
                   Result& r) {
  const auto& moves = p.canon.moves;
  for (std::size_t li = 0; li < p.lines.size(); ++li) {
    const auto k = r.actions[li].kind;
    if (k == Kind::Split || k == Kind::Expand) {
      ++r.blocks_changed;
      r.actions[li].changed = true;
    } else if (k == Kind::Feed) {
      const auto mi = line_moves[li].front();
      std::size_t f = mi;
      for (auto m : line_moves[li])
        if (moves[m].kind != CanonMove::Kind::Traverse) {
          f = m;
          break;
        }
      if (std::abs(r.optimized[f].front().feed - moves[f].feed) > 1e-3 * moves[f].feed) {
        ++r.blocks_changed;
        r.actions[li].changed = true;
      }
    }
  }
}

}  // namespace

Result optimize(const Program& p, const systems::e_adaptive::Settings& e, const Options& opt) {
  Result r;
  r.limit = e.rig.controller.load_limit;
  // With [chatter]: the margin of every sample in cut (chatter.hpp), which the feeds respect
  // (first: its machine file's errors before the prediction's work).
  ChatterLimit chatter(e.chatter);
  r.original = programmed(p.canon);
  r.before = predict(p.canon, r.original, e, opt);
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  r.chatter = chatter.enabled();
  if (r.chatter) chatter_margins(r.before.s, chatter, cut, opt.z_origin_mm);
  // Moves of each line; lines that must not change.
  std::vector<std::vector<std::size_t>> line_moves;
  MoveRoles roles = move_roles(p, opt, line_moves);
  finishing_passes(p.canon.moves, r.before.s, opt, roles);
  if (r.before.rapid_in_material_s > 0.0) keep_after_rapid(p, r.before, opt, roles.kept);
  Plan chosen = choose_feeds(p.canon, r.before, e, opt, roles);
  if (opt.blends) {  // the blends at the chosen splits cut a path of their own (refeed)
    Prediction trial = predict(p.canon, chosen, e, opt);
    if (r.chatter) chatter_margins(trial.s, chatter, cut, opt.z_origin_mm);
    refeed(p.canon, chosen, trial, e, opt, roles);
  }
  write_actions(p, line_moves, roles, chosen, opt, r);
  r.after = predict(p.canon, r.optimized, e, opt);
  if (r.chatter) {
    chatter_margins(r.after.s, chatter, cut, opt.z_origin_mm);
    flag_chatter(r.optimized, r.after.s);
  }
  count_changed(p, line_moves, r);
  return r;
}

}  // namespace lathectl::optimize
