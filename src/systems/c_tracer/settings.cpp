// System C's section reader: every key once, with its range, one line of meaning (the notes of
// docs/scenario-reference.md) and its shop → SI factor; absent keys keep Settings' defaults. The
// template's CSV file (points x_mm,diameter_mm) is a data format, read here as it always was.
#include "systems/c_tracer/settings.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::systems::c_tracer {

namespace {
using io::Range;
using io::TableReader;

constexpr double kMm = 1e-3;
constexpr double kDeg = std::numbers::pi / 180.0;

// template.csv: one point x_mm,diameter_mm a line; empty lines, # comments and a header skipped.
void read_csv(TableReader& tp, const std::string& scenario_file, RigConfig& c) {
  tp.check(!tp.has("features"), "csv", "give either csv or features");
  const std::string rel = tp.string("csv");
  tp.document("csv",
      "points x_mm,diameter_mm, relative to the scenario file, instead of features; ≤ 16 MiB");
  if (tp.is_describing()) return;
  const auto path = (std::filesystem::path(scenario_file).parent_path() / rel).string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) ||
      std::filesystem::file_size(path, ec) > (16u << 20))
    tp.fail("csv", "expected a regular file of at most 16 MiB: " + path);
  std::ifstream in(path);
  if (!in) tp.fail("csv", "cannot open " + path);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0])))
      continue;
    double xm = 0.0, dm = 0.0;
    char comma = 0;
    std::istringstream ls(line);
    if (!(ls >> xm >> comma >> dm) || comma != ',' || !std::isfinite(xm) || !(dm > 0.0))
      throw io::InputError(
          io::located(path, n, 0, "expected 'x_mm,diameter_mm' with a diameter > 0"));
    if (!c.profile.xs().empty() && xm * 1e-3 < c.profile.xs().back())
      throw io::InputError(io::located(path, n, 0, "x_mm must not decrease"));
    c.profile.add_point(xm * 1e-3, 0.5e-3 * dm);
  }
  if (c.profile.xs().size() < 2) tp.fail("csv", "at least two points expected in " + path);
  c.features.push_back({"csv", c.profile.xs().front(), c.profile.xs().back()});
}

// One feature from the current point (x, y), which it moves to its end.
void read_feature(TableReader& f, RigConfig& c, double& x, double& y) {
  const std::string kind =
      f.pick({"type", {}, "line (cylinder), cone, step or arc"}, {"line", "cone", "step", "arc"});
  const bool all = f.is_describing();  // describing: every feature's keys
  double len = 0.0, ang = 0.0, hgt = 0.0, r = 0.0;
  if (kind == "line" || kind == "cone" || kind == "arc" || all)
    f.require({"length_mm", {0.0, 1e4, true, false}, "line, cone, arc: length along x", kMm}, len);
  if (kind == "cone" || all) {
    f.require({"angle_deg", Range::closed(-89.0, 89.0),
               "cone: α > 0 when the diameter grows along +x; −β < α < 180° − β", kDeg},
              ang);
    f.check(!(ang <= -c.beta_rad || ang + c.beta_rad >= std::numbers::pi), "angle_deg",
            "the slide cannot follow a cone with α ≤ −β or α + β ≥ 180°");
  }
  if (kind == "step" || kind == "arc" || all)
    f.require({"height_mm", Range::closed(-1e3, 1e3),
               "step, arc: radial rise (a step must be ≥ 0: no step down)", kMm},
              hgt);
  if (kind == "arc" || all)
    f.require({"radius_mm",
               {0.0, 1e5, true, false},
               "arc: convex circle through both ends, ≥ half the chord",
               kMm},
              r);
  TracerFeature feat{kind, x, x};
  if (kind == "line") {
    x += len;
    c.profile.add_point(x, y);
  } else if (kind == "cone") {
    x += len;
    y += len * std::tan(ang);
    c.profile.add_point(x, y);
  } else if (kind == "step") {
    f.check(hgt >= 0.0, "height_mm",
            "a backward-inclined slide cannot follow a step down (α = −90° < −β)");
    y += hgt;
    c.profile.add_point(x, y);
  } else {  // arc: circle of the given radius through the current point and (x+len, y+h), convex
    const double chord = std::hypot(len, hgt);
    f.check(r >= 0.5 * chord, "radius_mm", "smaller than half the chord: no such arc");
    const double mx = x + 0.5 * len, my = y + 0.5 * hgt;
    const double dist = std::sqrt(r * r - 0.25 * chord * chord);
    // centre on the inner side (below the chord): a convex arc
    const double nx = hgt / chord, ny = -len / chord;
    const double cx = mx + dist * nx, cy = my + dist * ny;
    const double a0 = std::atan2(y - cy, x - cx), a1 = std::atan2(y + hgt - cy, x + len - cx);
    double prev_x = x;
    for (int k = 1; k <= 40; ++k) {
      const double ak = a0 + (a1 - a0) * k / 40.0;
      const double px = cx + r * std::cos(ak);
      // The template is y(x): the arc must not run backward nor past its own end in x.
      f.check(!(px < prev_x - 1e-12 || px > x + len + 1e-12), "radius_mm",
              "this arc would run backward in x (the template must be a function of x): "
              "give a larger radius or a longer length");
      prev_x = std::max(px, prev_x);
      c.profile.add_point(prev_x, cy + r * std::sin(ak));
    }
    x += len;
    y += hgt;
  }
  feat.x_end_m = x;
  f.finish();
  c.features.push_back(feat);
}

void read_template(TableReader& root, const std::string& scenario_file, RigConfig& c) {
  auto tp = root.table("template", true);
  root.document("template", "the template the stylus follows: features or a CSV file");
  const bool csv = tp->has("csv");
  if (csv || tp->is_describing()) read_csv(*tp, scenario_file, c);
  double x = 0.0, y = 0.0;
  if (!csv) {
    tp->read({"start_x_mm", Range::any(), "features only: where the template starts", kMm}, x);
    tp->require({"start_diameter_mm",
                 {0.0, 1e4, true, false},
                 "features only: the template's diameter at its start",
                 0.5e-3},
                y);
    if (!tp->is_describing()) c.profile.add_point(x, y);
  }
  for (auto& f : tp->tables("features")) read_feature(f, c, x, y);
  tp->document("features", "array of {type = line | cone | step | arc, ...}, at least one");
  tp->check(!c.features.empty(), "features",
            "at least one feature {type = line | cone | step | arc, ...}");
  tp->finish();
}

void read_models(TableReader& root, Settings& st) {
  auto& c = st.rig;
  {
    auto mt = root.table("model", true);
    root.document("model", "which slide model runs, and which one is overlaid");
    c.nonlinear = mt->pick({"type", {}, "the seed's (8)-(9), or the nonlinear servo"},
                           {"linear", "nonlinear"}) == "nonlinear";
    st.compare =
        mt->pick({"compare", {},
                   "a second run, overlaid; a nonlinear run compared with \"linear\" uses the "
                   "servo's own linearisation, P0 = Coulomb friction + initial load"},
                  {"linear", "nonlinear"}, "");
    mt->finish();
  }
  if (auto li = root.table("linear")) {
    root.document("linear", "the linear model (8)-(9); required with type = \"linear\"");
    li->require({"E0_N_per_mm", {0.0, 1e9, true, false}, "E0, N per mm of spool opening", 1e3},
                c.linear.E0_N_per_m);
    li->require({"C0_per_s", {0.0, 1e6, true, false}, "C0, velocity gain ∂V/∂h"},
                c.linear.C0_per_s);
    li->require({"P0_N", Range::closed(0, 1e6), "P0, cutting + dry friction (constant)"},
                c.linear.P0_N);
    li->finish();
  } else {
    root.check(c.nonlinear, "linear", "a linear model needs [linear] E0_N_per_mm, C0_per_s, P0_N");
  }
  if (auto sv = root.table("servo")) {
    root.document("servo",
        "the nonlinear servo; required with type = \"nonlinear\" or compare = \"nonlinear\"");
    sv->require({"supply_MPa", {0.0, 100.0, true, false}, "supply pressure p_s", 1e6}, c.supply_Pa);
    sv->read({"discharge_coefficient", {0.0, 1.0, true, false}, "C_d"}, c.discharge_coefficient);
    sv->require({"port_width_mm", {0.0, 1e3, true, false}, "w, the spool's port width", 1e-3},
                c.area_gradient_m);
    sv->read({"oil_density_kg_per_m3", Range::closed(500.0, 1500.0), "ρ"}, c.density_kg_per_m3);
    sv->read({"overlap_um", Range::closed(0, 1e4), "u, the spool's overlap (a dead zone)", 1e-6},
             c.overlap_m);
    // Converted as before the described reader (× cm³ ÷ 60 ÷ MPa, not × one factor): the same bits.
    double leak = 0.0;
    sv->require({"clearance_leak_cm3_per_min_per_MPa",
                 {0.0, 1e6, true, false},
                 "K_c, the clearance leakage"},
                leak);
    c.clearance_leak_m3_per_s_Pa = leak * 1e-6 / 60.0 / 1e6;
    sv->require({"piston_area_cm2", {0.0, 1e4, true, false}, "A", 1e-4}, c.piston_area_m2);
    sv->require(
        {"volume_cm3", {0.0, 1e6, true, false}, "V_t, the oil volume under compression", 1e-6},
        c.total_volume_m3);
    sv->read({"bulk_modulus_MPa", Range::closed(100.0, 1e5), "B of the oil", 1e6},
             c.bulk_modulus_Pa);
    sv->finish();
  } else {
    root.check(!c.nonlinear && st.compare != "nonlinear", "servo",
               "the nonlinear model needs [servo]");
  }
}

void read_friction_cutting(TableReader& root, const io::MaterialLibrary& lib, RigConfig& c) {
  if (auto fr = root.table("friction")) {
    root.document("friction", "the slide's friction (nonlinear servo): Stribeck, with stiction");
    fr->read({"coulomb_N", Range::closed(0, 1e6), "F_c, Coulomb friction"}, c.coulomb_N);
    c.static_N = c.coulomb_N;
    fr->read({.key = "static_N",
              .range = Range::closed(0, 1e6),
              .doc = "F_s, static friction (default coulomb_N)",
              .derived = "coulomb_N"},
             c.static_N);
    fr->check(c.static_N >= c.coulomb_N, "static_N", "must be ≥ coulomb_N (falling friction)");
    fr->read(
        {"stribeck_velocity_mm_per_s", {0.0, 1e4, true, false}, "v_s of the Stribeck curve", 1e-3},
        c.stribeck_velocity_m_per_s);
    fr->read({"viscous_N_s_per_m", Range::closed(0, 1e9), "b, viscous friction"},
             c.viscous_N_s_per_m);
    fr->finish();
  }
  if (auto cu = root.table("cutting")) {
    root.document("cutting",
        "a cutting load from the handbook model (needs [material]); without it P0 is constant");
    io::read_material_tool(root, lib, c.cutting);
    cu->require({"blank_diameter_mm",
                 {0.0, 1e4, true, false},
                 "the blank: depth = blank radius − tool radius",
                 kMm},
                c.blank_diameter_m);
    cu->finish();
  }
}

void read_all(TableReader& root, const io::Scenario& sc, const io::MaterialLibrary& lib,
              Settings& st) {
  auto& c = st.rig;
  auto m = root.table("machine", true);
  root.document("machine", "feed and spindle speed: the carriage speed V_pr = s·n/60");
  m->require({"feed_mm_per_rev", {0.0, 10.0, true, false}, "s", kMm}, c.feed_m_per_rev);
  m->require({"spindle_rpm", {0.0, 2e4, true, false}, "n"}, c.spindle_rpm);
  m->finish();

  auto sl = root.table("slide", true);
  root.document("slide", "the tracer slide");
  sl->require({"guide_angle_deg", {0.0, 90.0, true, false}, "β, the guide's inclination", kDeg},
              c.beta_rad);
  sl->require({"lever_ratio", {0.0, 1e3, true, false}, "i = spool opening per stylus deflection"},
              c.linear.lever_ratio);
  sl->require({"mass_kg", {0.0, 1e5, true, false}, "M, reduced"}, c.linear.mass_kg);
  sl->finish();

  read_template(root, sc.file, c);
  read_models(root, st);
  read_friction_cutting(root, lib, c);
}

}  // namespace

const std::array<io::CriterionKey, 3> kAcceptanceKeys{{
    {"max_profile_error_um", "largest radial profile error |δy| at equal x", false, 100.0,
     Range::closed(0, 1e5),
     "largest |δy|, the part's radius against the template's at equal x, over the whole "
     "template (shoulders masked as in the report), µm (default 100: 0.1 mm, a copying "
     "slide's usual accuracy)"},
    {"max_axial_error_um", "largest axial profile error |δx| at equal y", false, 0.0,
     Range::closed(0, 1e5),
     "largest |δx| where the template slopes by more than 10° (0: not judged, the default)"},
    {"max_waviness_um", "largest cone waviness (peak-to-peak δy)", false, 0.0,
     Range::closed(0, 1e5),
     "largest peak-to-peak δy about its trend over a cone's second half, the stick-slip's "
     "trace (0: not judged, the default)"},
}};

std::unique_ptr<io::SystemSettings> read_settings(TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib) {
  auto st = std::make_unique<Settings>();
  try {
    read_all(root, sc, lib, *st);
  } catch (const std::invalid_argument& e) {  // the template's points, rejected by the profile
    io::throw_at_key(sc, e, "template");
  }
  io::read_acceptance(root, st->acceptance);
  return st;
}

}  // namespace lathectl::systems::c_tracer
