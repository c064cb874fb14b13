#include "lathectl/io/sections.hpp"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>

namespace lathectl::io {

void read_run(TableReader& root, RunSettings& run) {
  auto t = root.table("run", true);
  t->require({"duration_s", {0.0, 86400.0, true, false},
              "run length (A, D's longest full-model part); in B and E an upper limit (B stops "
              "after its cut, E after its last pass); C runs the whole template regardless"},
             run.duration_s);
  t->read({"step_s", Range::closed(1e-7, 0.01), "fixed integration step"}, run.step_s);
  t->read({"record_interval_s", Range::closed(1e-7, 10.0), "interval of the recorded channels"},
          run.record_interval_s);
  t->check(run.record_interval_s >= run.step_s, "record_interval_s", "must be ≥ step_s");
  t->check(run.duration_s / run.step_s <= 5e8, "step_s",
           "duration_s / step_s must not exceed 5e8 steps");
  t->read({"seed", Range::closed(0, 9.2e18),
           "seeds every random source (noise, random allowance); the same seed gives the same run"},
          run.seed);
  t->finish();
}

namespace {
// [tool] front_angle_deg and back_angle_deg: the insert's straight edges (LinuxCNC's tool table
// I and J, AXIS's convention), into angles[0] and angles[1].
void read_insert_angles(TableReader& tool, double* angles) {
  angles[0] = tool.number("front_angle_deg", Range::closed(-360.0, 360.0), angles[0]);
  tool.document("front_angle_deg",
                "the insert's front angle [°], LinuxCNC's tool table I: its straight edge leaves "
                "the nose along machine (x, z) = (sin a, cos a) (AXIS's lathe tool drawing; "
                "clockwise from +Z as LinuxCNC's lathe docs draw it); with back_angle_deg both 0 "
                "(the default): the nose alone, no straight edges (a CNMG in a 95° holder: 85 "
                "and 5 at orientation 2, 95 and 175 at 1)");
  angles[1] = tool.number("back_angle_deg", Range::closed(-360.0, 360.0), angles[1]);
  tool.document("back_angle_deg",
                "the insert's back angle [°], LinuxCNC's tool table J; the included angle "
                "|front − back| is in (0°, 180°)");
  const double inc = std::abs(angles[0] - angles[1]);
  if ((angles[0] != 0.0 || angles[1] != 0.0) && !(inc > 0.0 && inc < 180.0))
    tool.fail("back_angle_deg", "the insert's included angle |front_angle_deg − back_angle_deg| "
                                "must be in (0°, 180°), got " + std::to_string(inc) + "°");
}
}  // namespace

void read_material_tool(TableReader& root, const MaterialLibrary& lib,
                        cutting::CuttingModel::Params& cutting, cutting::DisturbanceParams* wear,
                        bool kienzle_only, int* orientation, double* angles) {
  auto mat = root.table("material", true);
  root.document("material", "the work material, from the library data/materials.toml");
  const std::string name = mat->string("name");
  mat->document("name", "a material of data/materials.toml (lathectl check lists them on error)");
  const cutting::Material* found = lib.find(name);
  if (!found && mat->is_describing() && !lib.names().empty()) found = lib.find(lib.names().front());
  if (!found) {
    std::string known;
    for (const auto& n : lib.names()) known += (known.empty() ? "" : ", ") + n;
    mat->fail("name", "unknown material \"" + name + "\" (data/materials.toml has: " + known + ")");
  }
  cutting.material = *found;
  cutting.form =
      (kienzle_only ? mat->choice("force_model", {"kienzle"}, "kienzle")
                    : mat->choice("force_model", {"handbook", "kienzle"}, "handbook")) == "kienzle"
          ? cutting::ForceForm::Kienzle
          : cutting::ForceForm::Handbook;
  mat->document("force_model",
                kienzle_only ? "Kienzle b·h^(1−m): the chatter model needs dF/db at the chip"
                             : "the handbook's C·t^x·s^y·V^n, or Kienzle's b·h^(1−m)");
  mat->finish();

  if (auto tool = root.table("tool")) {
    root.document("tool", "the insert's geometry (and, where the system models it, its wear)");
    tool->read({.key = "nose_radius_mm",
                .range = {0.0, 10.0, true, false},
                .doc = "r_ε: with the feed, sets the chip and the roughness",
                .plausible = Range::closed(0.05, 4.0)},
               cutting.nose_radius_mm);
    cutting.approach_angle_deg = tool->number("approach_angle_deg", {0.0, 95.0, true, false}, 90.0);
    tool->document("approach_angle_deg",
                   "κ_r: splits the chip into width b = t/sin κ and h = s·sin κ (Kienzle form; up "
                   "to 95°, the common 93° and 95° turning tools: past 90° the split is the "
                   "straight edge's geometry and the coefficients, fitted at κ ≤ 90°, are "
                   "extrapolated)");
    if (orientation) {
      *orientation = static_cast<int>(tool->integer("orientation", 0, 9, *orientation));
      tool->document("orientation",
                     "LinuxCNC's lathe tool orientation Q (tool table Q): the programmed point is "
                     "this imaginary tool tip of the nose (2: turning and facing toward the chuck, "
                     "the tip's x the nose's lowest point, its z the nose's leading point; 0 or "
                     "9: the nose's centre)");
    }
    if (angles) read_insert_angles(*tool, angles);
    if (wear) {
      if (auto w = tool->table("wear")) {
        wear->wear_VB0_mm = w->number("initial_VB_mm", Range::closed(0, 2), 0.0);
        wear->wear_rate_mm_per_min = w->number("rate_mm_per_min", Range::closed(0, 1), 0.0);
        wear->wear_force_gain_per_mm = w->number("force_gain_per_mm", Range::closed(0, 20), 0.0);
        tool->document("wear", "flank wear VB growing in cutting time, raising the force");
        w->document("initial_VB_mm", "VB at the start");
        w->document("rate_mm_per_min", "dVB/dt while cutting");
        w->document("force_gain_per_mm", "relative force increase per mm of VB");
        w->finish();
      }
    }
    tool->finish();
  }
}

std::vector<sensors::SensorFault> read_faults(TableReader& root) {
  std::vector<sensors::SensorFault> out;
  for (auto& f : root.tables("fault")) {
    sensors::SensorFault sf;
    const std::string k = f.choice("kind", {"nan", "stuck", "out_of_range"});
    sf.kind = k == "nan"     ? sensors::SensorFault::Kind::NotFinite
              : k == "stuck" ? sensors::SensorFault::Kind::Stuck
                             : sensors::SensorFault::Kind::OutOfRange;
    sf.at_s = f.number("at_s", Range::non_negative());
    sf.duration_s = f.number("duration_s", Range::positive(), 1e300);
    root.document("fault", "injected sensor faults, to see the controller's monitor react");
    f.document("kind", "nan: the reading is not a number; stuck: it freezes; out_of_range: far "
                       "outside the sensor's range");
    f.document("at_s", "when the fault starts");
    f.document("duration_s", "how long it lasts (default: to the end)");
    f.finish();
    out.push_back(sf);
  }
  return out;
}

// The spindle drive (systems B and E). With `defaults`, every key is optional and keeps the
// value already in `s`.
void read_spindle(TableReader& sp, drives::SpindleDrive::Params& s, bool defaults) {
  using P = Param;
  const P inertia{"inertia_kg_m2", Range::positive(),
                  "J: spindle, chuck and part reduced to the spindle"};
  const P torque{"max_torque_N_m", Range::positive(), "T_max of the drive"};
  const P power{.key = "max_power_kW",
                .range = Range::positive(),
                .doc = "P_max, mechanical, at the spindle",
                .scale = 1e3,
                .plausible = Range::closed(0.1, 500.0)};
  if (defaults) {
    sp.read(inertia, s.inertia_kg_m2);
    sp.read(torque, s.max_torque_N_m);
    sp.read(power, s.max_power_W);
  } else {
    sp.require(inertia, s.inertia_kg_m2);
    sp.require(torque, s.max_torque_N_m);
    sp.require(power, s.max_power_W);
  }
  sp.read({"viscous_N_m_s", Range::closed(0, 1e4), "b, viscous friction"}, s.viscous_N_m_s);
  sp.read({"efficiency", {0.0, 1.0, true, false}, "η of motor and transmission"}, s.efficiency);
  sp.read({"idle_p0_W", Range::closed(0, 1e6), "idle power P_idle(n) = p0 + p1·n + p2·n²: p0"},
          s.idle_p0_W);
  sp.read({"idle_p1_W_per_rpm", Range::closed(0, 1e3), "idle power: p1"}, s.idle_p1_W_per_rpm);
  sp.read({"idle_p2_W_per_rpm2", Range::closed(0, 10), "idle power: p2"}, s.idle_p2_W_per_rpm2);
  sp.read({"kp_N_m_s", Range::positive(), "speed loop: proportional gain, N·m per rad/s"},
          s.kp_N_m_s);
  sp.read({"ti_s", Range::positive(), "speed loop: integral time"}, s.ti_s);
  sp.read({"max_accel_rpm_per_s", Range::positive(), "speed command ramp"},
          s.max_accel_rpm_per_s);
  sp.read({"min_rpm", Range::positive(), "lowest speed the drive holds"}, s.min_rpm);
  sp.read({.key = "max_rpm",
           .range = Range::positive(),
           .doc = "highest speed",
           .plausible = Range::closed(10.0, 2e4)},
          s.max_rpm);
  sp.check(s.max_rpm > s.min_rpm, "max_rpm", "must exceed min_rpm");
  sp.finish();
}

namespace {
// An angle in degrees, converted as the machine file's reader always did (deg·π/180).
double read_angle_rad(TableReader& t, std::string_view doc) {
  double deg = 0.0;
  t.read({"angle_deg", Range::closed(-90, 90), doc}, deg);
  return deg * std::numbers::pi / 180.0;
}
}  // namespace

std::vector<dynamics::Mode> read_modes(TableReader& root) {
  std::vector<dynamics::Mode> modes;
  for (auto& m : root.tables("mode")) {
    dynamics::Mode md;
    // Plausible: a lathe's tool, turret or part mode (6 N/µm written as 6 would be 6 N/m).
    m.require({.key = "stiffness_N_per_m",
               .range = {0.0, 1e13, true, false},
               .doc = "k, the mode's stiffness",
               .plausible = Range::closed(1e5, 1e11)},
              md.stiffness_N_per_m);
    m.require({.key = "damping_ratio",
               .range = {0.0, 1.0, true, true},
               .doc = "ζ, the mode's damping ratio",
               .plausible = Range::closed(1e-4, 0.3)},
              md.damping_ratio);
    m.require({.key = "natural_frequency_Hz",
               .range = {0.0, 1e6, true, false},
               .doc = "f_n, the mode's natural frequency",
               .plausible = Range::closed(1.0, 2e4)},
              md.natural_frequency_Hz);
    md.angle_rad = read_angle_rad(m, "θ, the mode's direction to the chip-thickness direction");
    m.finish();
    modes.push_back(md);
  }
  return modes;
}

void read_beam_material(TableReader& p, dynamics::BeamPart& b, bool defaults) {
  const Param e{"youngs_modulus_GPa",
                {0.0, 1e4, true, false},
                defaults ? "E, Young's modulus of the part"
                         : "E (required here; 210 by default in a system-B scenario)",
                1e9};
  const Param rho{"density_kg_per_m3",
                  {0.0, 1e5, true, false},
                  defaults ? "ρ, density of the part"
                           : "ρ (required here; 7850 by default in a system-B scenario)"};
  if (defaults) {
    p.read(e, b.youngs_modulus_Pa);
    p.read(rho, b.density_kg_per_m3);
  } else {
    p.require(e, b.youngs_modulus_Pa);
    p.require(rho, b.density_kg_per_m3);
  }
  p.require({"damping_ratio", {0.0, 1.0, true, true}, "ζ of each bending mode"}, b.damping_ratio);
  b.angle_rad = read_angle_rad(p, "direction of the bending modes to the chip thickness");
}

}  // namespace lathectl::io
