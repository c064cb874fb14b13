// optimized.ngc: the program's lines with the chosen feeds — an F word per line, a line split
// into pieces, or a cycle line expanded into its moves — checked by interpreting it again.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <string>

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
std::string feed_text(const CanonMove& m, double f) {
  return number(f, m.per_rev ? 4 : 1);
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

std::string move_text(const CanonMove& m, double from, double to, double feed) {
  const auto [xs, zs] = point_at(m, from);
  const auto [xe, ze] = point_at(m, to);
  if (m.kind == CanonMove::Kind::Traverse) return "G0 X" + number(xe, 4) + " Z" + number(ze, 4);
  std::string t = m.kind == CanonMove::Kind::Line ? "G1" : (m.rotation < 0 ? "G2" : "G3");
  t += " X" + number(xe, 4) + " Z" + number(ze, 4);
  if (m.kind == CanonMove::Kind::Arc)
    t += " I" + number(m.xc - xs, 4) + " K" + number(m.zc - zs, 4);
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
  constexpr double kTol = 2e-3;  // mm (the program's 4 decimals, the interpreter's 4)
  std::size_t j = 0;
  for (const CanonMove* o : a) {
    for (;;) {
      if (j >= b.size()) return false;
      const CanonMove& m = *b[j++];
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

}  // namespace

// The text of optimized.ngc for these actions; fills each piece's output line.
std::string write_program(const Program& p, const std::vector<LineAction>& act, Plan& plan,
                          const std::vector<std::vector<std::size_t>>& line_moves,
                          std::vector<std::string>& out) {
  out.clear();
  bool changed = false;
  for (std::size_t li = 0; li < p.lines.size(); ++li) {
    const std::string& text = p.lines[li];
    const int line = static_cast<int>(li + 1);
    const auto& mv = line_moves[li];
    auto here = [&] { return static_cast<int>(out.size() + 1); };
    auto set_lines = [&](int at) {
      for (auto mi : mv)
        for (auto& pc : plan[mi]) pc.out_line = at;
    };
    const CanonMove* first_feed = nullptr;
    for (auto mi : mv)
      if (p.canon.moves[mi].kind != CanonMove::Kind::Traverse && !first_feed)
        first_feed = &p.canon.moves[mi];
    switch (act[li].kind) {
      case Kind::None:
        set_lines(here());
        out.push_back(text);
        break;
      case Kind::Keep: {
        const auto ws = words(text);
        const bool has_f =
            std::any_of(ws.begin(), ws.end(), [](const Word& w) { return w.letter == 'F'; });
        if (changed && first_feed && !has_f)
          out.push_back("F" + feed_text(*first_feed, first_feed->feed) +
                        " (lathectl: the programmed feed of the kept line " + std::to_string(line) +
                        ")");
        set_lines(here());
        out.push_back(text);
        break;
      }
      case Kind::Feed: {
        std::size_t fi = mv.front();
        for (auto mi : mv)
          if (p.canon.moves[mi].kind != CanonMove::Kind::Traverse) {
            fi = mi;
            break;
          }
        const double f = plan[fi].front().feed;
        set_lines(here());
        out.push_back(with_feed(text, feed_text(*first_feed, f)).value_or(text));
        changed = true;
        break;
      }
      case Kind::Split: {
        const std::size_t mi = mv.front();
        const CanonMove& m = p.canon.moves[mi];
        auto& pcs = plan[mi];
        const std::size_t n = pcs.size();
        for (std::size_t k = 0; k + 1 < n; ++k) {
          pcs[k].out_line = here();
          out.push_back(move_text(m, pcs[k].from, pcs[k].to, pcs[k].feed) + " (lathectl: line " +
                        std::to_string(line) + ", piece " + std::to_string(k + 1) + " of " +
                        std::to_string(n) + ")");
        }
        pcs.back().out_line = here();
        if (m.kind == CanonMove::Kind::Line) {
          out.push_back(with_feed(text, feed_text(m, pcs.back().feed)).value_or(text));
        } else {  // an arc's centre words are relative to its start: the last piece in full
          out.push_back(move_text(m, pcs.back().from, 1.0, pcs.back().feed) + " (lathectl: line " +
                        std::to_string(line) + ", piece " + std::to_string(n) + " of " +
                        std::to_string(n) + ": " + commented(text) + ")");
        }
        changed = true;
        break;
      }
      case Kind::Expand: {
        out.push_back("(lathectl: line " + std::to_string(line) + " expanded into its " +
                      std::to_string(mv.size()) + " moves: " + commented(text) + ")");
        for (auto mi : mv) {
          const CanonMove& m = p.canon.moves[mi];
          if (move_length(m) <= 1e-6) {
            for (auto& pc : plan[mi]) pc.out_line = here();
            continue;
          }
          for (auto& pc : plan[mi]) {
            pc.out_line = here();
            out.push_back(move_text(m, pc.from, pc.to, pc.feed));
          }
        }
        changed = true;
        break;
      }
    }
  }
  std::string ngc;
  for (const auto& l : out) ngc += l + "\n";
  return ngc;
}

Result optimize(const Program& p, const systems::e_adaptive::Settings& e, const Options& opt) {
  Result r;
  r.limit = e.rig.controller.force_limit;
  const auto& moves = p.canon.moves;
  r.original = programmed(p.canon);
  r.before = predict(p.canon, r.original, e, opt);
  // With [chatter]: the margin of every sample in cut (chatter.hpp), which the feeds respect.
  ChatterLimit chatter(e.chatter);
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  r.chatter = chatter.enabled();
  if (r.chatter) chatter_margins(r.before.s, chatter, cut, opt.z_origin_mm);
  // Moves of each line; lines that must not change.
  std::vector<std::vector<std::size_t>> line_moves(p.lines.size());
  std::vector<bool> kept(moves.size(), false);
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const int l = moves[i].line;
    if (l < 1 || static_cast<std::size_t>(l) > p.lines.size()) continue;
    line_moves[static_cast<std::size_t>(l - 1)].push_back(i);
    kept[i] = keep_marked(p.lines[static_cast<std::size_t>(l - 1)]);
  }
  Plan chosen = choose_feeds(p.canon, r.before, e, opt, kept);
  if (opt.blends) {  // the blends at the chosen splits cut a path of their own (refeed)
    Prediction trial = predict(p.canon, chosen, e, opt);
    if (r.chatter) chatter_margins(trial.s, chatter, cut, opt.z_origin_mm);
    refeed(p.canon, chosen, trial, e, opt, kept);
  }
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool allow_split = attempt == 0;
    r.actions.assign(p.lines.size(), {});
    r.optimized = r.original;
    for (std::size_t li = 0; li < p.lines.size(); ++li) {
      const auto& mv = line_moves[li];
      std::vector<std::size_t> feeds;
      bool synced = false, comp = false, mixed = false;
      for (auto mi : mv) {
        if (moves[mi].kind == CanonMove::Kind::Traverse) continue;
        feeds.push_back(mi);
        synced = synced || moves[mi].synced;
        comp = comp || moves[mi].compensated;
        mixed = mixed || moves[mi].per_rev != moves[feeds.front()].per_rev;
      }
      if (feeds.empty()) continue;
      auto& a = r.actions[li];
      const std::string& text = p.lines[li];
      if (keep_marked(text) || synced || mixed || !with_feed(text, "1")) {
        a = {Kind::Keep, keep_marked(text) ? "marked (lathectl:keep)"
                         : synced          ? "threading"
                         : mixed           ? "G94 and G95 moves on one line"
                                           : "its F word is an expression"};
        continue;
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
    std::vector<std::string> out_lines;
    r.ngc = write_program(p, r.actions, r.optimized, line_moves, out_lines);
    const auto again = interpret(out_lines, p.file + " (optimised)", opt);
    if (same_path(p.canon, again)) break;
    if (!allow_split)
      throw std::runtime_error(p.file +
                               ": the optimised program leaves the original path "
                               "(lathectl optimize's fault: please report it)");
    r.splits_dropped = true;
  }
  r.after = predict(p.canon, r.optimized, e, opt);
  if (r.chatter) {
    chatter_margins(r.after.s, chatter, cut, opt.z_origin_mm);
    flag_chatter(r.optimized, r.after.s);
  }
  for (std::size_t li = 0; li < p.lines.size(); ++li) {
    const auto k = r.actions[li].kind;
    if (k == Kind::Split || k == Kind::Expand) {
      ++r.blocks_changed;
    } else if (k == Kind::Feed) {
      const auto mi = line_moves[li].front();
      std::size_t f = mi;
      for (auto m : line_moves[li])
        if (moves[m].kind != CanonMove::Kind::Traverse) {
          f = m;
          break;
        }
      if (std::abs(r.optimized[f].front().feed - moves[f].feed) > 1e-3 * moves[f].feed)
        ++r.blocks_changed;
    }
  }
  return r;
}

}  // namespace lathectl::optimize
