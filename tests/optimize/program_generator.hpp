#pragma once
// Valid turning programs nobody wrote by hand, for lathectl optimize's acceptance test: a bar of
// random diameter faced, roughed in passes (G1) to two diameters, finished along a contour with
// a chamfer, a concave fillet and a shoulder, sometimes grooved (T2) and threaded (T10: G76 or
// G33); radius (G8) or diameter (G7) mode, G95 or G94 feeds, G97 or G96 speeds. In some, the
// roughing is LinuxCNC's G71 cycle over the contour as a subroutine and the finish its G70; in
// others the G1 finishing contour runs under cutter compensation (G42, the tool table's nose).
// The generator knows which lines are finishing, plunges and threads, so that the test can check
// each kind.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace lathectl::optimize::testing {

struct GeneratedProgram {
  std::vector<std::string> lines;
  double blank_radius_mm = 0.0;
  std::vector<int> finishing_lines, plunge_lines, thread_lines;  // 1-based
  std::string summary;                                           // for failure messages
  bool cycles = false, compensation = false;                     // G71/G70; G42
};

inline GeneratedProgram generate_program(unsigned seed) {
  std::mt19937 rng(seed);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  auto chance = [&](double p) { return uni(0.0, 1.0) < p; };
  GeneratedProgram g;
  // Cycles and compensation from a generator of their own: the programs without them stay what
  // they were for the same seed.
  std::mt19937 rng_kind(seed * 7919u + 17u);
  const double kind = std::uniform_real_distribution<double>(0.0, 1.0)(rng_kind);
  g.cycles = kind < 0.3;
  g.compensation = !g.cycles && kind < 0.55;
  const bool diameter = chance(0.5);  // G7
  const bool css = chance(0.25);      // G96
  const bool per_min = !css && chance(0.3);  // G94
  const double R = std::round(uni(15.0, 25.0) * 2.0) / 2.0;
  const double r_fin = std::round((R - uni(3.0, 6.0)) * 10.0) / 10.0;
  const double q = std::round(uni(1.0, 3.0) * 10.0) / 10.0;     // fillet radius
  const double h = std::round(uni(0.5, 2.0) * 10.0) / 10.0;     // shoulder above the fillet
  const double r2 = std::min(r_fin + q + h, R - 1.0);
  // Compensation needs a shoulder above the fillet's end (r2 below it is a notch that a 0.4 mm
  // nose cannot follow: LinuxCNC refuses it as a gouge).
  g.compensation = g.compensation && r2 >= r_fin + q + 0.4;
  const double Ls = std::round(uni(8.0, 12.0));                 // the fillet starts at Z-Ls
  const double Lr = Ls + q + std::round(uni(3.0, 6.0));          // the shoulder ends at Z-Lr
  const double face = std::round(uni(0.3, 0.8) * 10.0) / 10.0;   // faced off the bar's end
  const double c = std::round(uni(0.5, 1.5) * 10.0) / 10.0;      // chamfer
  const double rpm = std::round(uni(1600.0, 2400.0));
  const double vc = std::round(uni(150.0, 220.0));
  g.blank_radius_mm = R;
  auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return std::string(b);
  };
  auto X = [&](double r) { return "X" + num(diameter ? 2.0 * r : r); };
  auto F = [&](double f_rev) { return "F" + num(per_min ? std::round(f_rev * rpm) : f_rev); };
  auto add = [&](const std::string& l) {
    g.lines.push_back(l);
    return static_cast<int>(g.lines.size());
  };
  add(std::string("G18 G21 G40 G90 ") + (per_min ? "G94" : "G95") + (diameter ? " G7" : " G8"));
  add("T1 M6");
  add(css ? "G96 D2500 S" + num(vc) + " M3" : "G97 S" + num(rpm) + " M3");
  add("G0 " + X(R + 2.0) + " Z2");
  // facing
  add("G0 Z" + num(-face));
  add("G1 " + X(-0.5) + " " + F(std::round(uni(0.1, 0.2) * 100.0) / 100.0));
  add("G0 Z2");
  add("G0 " + X(R + 2.0));
  // roughing: to r2 + 0.3 over Lr, then to r_fin + 0.3 up to the fillet
  auto passes = [&](double from, double to, double len) {
    const int n = static_cast<int>(std::ceil((from - to) / uni(1.0, 2.5)));
    const double f = std::round(uni(0.15, 0.3) * 100.0) / 100.0;
    for (int k = 1; k <= n; ++k) {
      add("G0 " + X(from - (from - to) * k / n));
      add("G1 Z" + num(-len) + " " + F(f));
      add("G0 " + X(R + 2.0));
      add("G0 Z2");
    }
  };
  if (!g.cycles) {
    passes(R, r2 + 0.3, Lr - 0.3);
    passes(r2 + 0.3, r_fin + 0.3, Ls + q - 0.3);
  }
  // finishing contour
  const double ff = std::round(uni(0.06, 0.12) * 100.0) / 100.0;
  if (g.cycles) {
    // The contour as LinuxCNC's G7x cycles take it: a subroutine from the chamfer's start to
    // above the bar, X rising and Z falling along it; G71 roughs to 0.3 mm of it (D: the stock
    // to leave, I: the depth of each pass, R: the retract), G70 finishes it in one pass.
    const double depth = std::round(uni(1.0, 2.5) * 10.0) / 10.0;
    const double fr = std::round(uni(0.15, 0.3) * 100.0) / 100.0;
    const std::size_t at = 1;  // the subroutine before the program's moves
    std::vector<std::string> sub{
        "o100 sub",
        "G1 " + X(r_fin - c) + " Z" + num(-face),
        "G1 " + X(r_fin) + " Z" + num(-face - c),
        "G1 Z" + num(-Ls),
        "G2 " + X(r_fin + q) + " Z" + num(-Ls - q) + " R" + num(q),
        "G1 " + X(r2),
        "G1 Z" + num(-Lr),
        "G1 " + X(R + 1.0),
        "o100 endsub"};
    g.lines.insert(g.lines.begin() + at, sub.begin(), sub.end());
    const int shift = static_cast<int>(sub.size());
    for (auto* v : {&g.finishing_lines, &g.plunge_lines, &g.thread_lines})
      for (int& l : *v) l += shift;
    add("G0 " + X(R + 2.0) + " Z2");
    add("G71 Q100 " + X(R + 2.0) + " Z2 D0.3 I" + num(depth) + " R0.5 " + F(fr));
    g.finishing_lines.push_back(
        add("G70 Q100 " + X(R + 2.0) + " Z2 D0 E0 P1 " + F(ff)));
    add("G0 " + X(R + 2.0) + " Z2");
  } else {
    // Under cutter compensation in some: G42 on the lead-in, the tool table's nose (T1: D1.6)
    // to the right of the path, G40 on the way out. The lead-in stands 2 mm out on the chamfer's
    // line: rs274 puts the tip of the compensated nose (T1's Q2) about 1.5 r beyond the lead-in
    // point along z (0.61 mm for D0.8), so from 0.5 mm out it entered the face at rapid (issue
    // 47: the plant now cuts the face where the program puts it, not a nose radius deeper), and
    // from 1 mm out with the table's D1.6 (the prediction cuts with the table's nose).
    const std::string on = g.compensation ? "G42 " : "", off = g.compensation ? "G40 " : "";
    add(on + "G0 " + X(r_fin - c - 2.0) + " Z" + num(-face + 2.0));
    g.finishing_lines.push_back(add("G1 " + X(r_fin) + " Z" + num(-face - c) + " " + F(ff)));
    g.finishing_lines.push_back(add("G1 Z" + num(-Ls)));
    g.finishing_lines.push_back(add("G2 " + X(r_fin + q) + " Z" + num(-Ls - q) + " R" + num(q)));
    g.finishing_lines.push_back(add("G1 " + X(r2)));
    g.finishing_lines.push_back(add("G1 Z" + num(-Lr)));
    g.finishing_lines.push_back(add("G1 " + X(R + 1.0)));
    add(off + "G0 " + X(R + 2.0) + " Z2");
  }
  if (chance(0.5)) {  // a 3 mm groove on the finished diameter
    const double zg = std::round(uni(-face - c - 3.5, -Ls + 1.5));
    add("T2 M6");
    add("G0 " + X(r_fin + 1.0) + " Z" + num(zg));
    g.plunge_lines.push_back(
        add("G1 " + X(r_fin - uni(0.5, 1.2)) + " " + F(std::round(uni(0.03, 0.06) * 100.0) / 100.0)));
    add("G0 " + X(R + 2.0));
    add("G0 Z2");
  }
  if (chance(0.6)) {  // a thread on the finished diameter, pitch 1–2 mm
    const double p = chance(0.5) ? 1.5 : chance(0.5) ? 1.0 : 2.0;
    add("T10 M6");
    if (chance(0.6)) {
      add("G0 " + X(r_fin + 1.0) + " Z2");
      const double k = 0.6134 * p * (diameter ? 2.0 : 1.0);
      g.thread_lines.push_back(add("G76 P" + num(p) + " Z" + num(-Ls + 3.0) + " I" +
                                   num(diameter ? -2.0 : -1.0) + " J" + num(k / 6.0) + " K" +
                                   num(k) + " R1.5 Q29.5 H1"));
    } else {
      add("G0 " + X(r_fin - 0.1) + " Z2");
      g.thread_lines.push_back(add("G33 Z" + num(-Ls + 3.0) + " K" + num(p)));
      add("G0 " + X(R + 2.0));
    }
  }
  add("G0 " + X(R + 5.0) + " Z20");
  add("M5");
  add("M2");
  g.summary = "seed " + std::to_string(seed) + ": R " + num(R) + ", r " + num(r_fin) + "/" +
              num(r2) + (diameter ? ", G7" : ", G8") + (css ? ", G96" : per_min ? ", G94" : "") +
              (g.cycles ? ", G71/G70" : g.compensation ? ", G42" : "");
  return g;
}

}  // namespace lathectl::optimize::testing
