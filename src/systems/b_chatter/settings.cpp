#include "systems/b_chatter/settings.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/b_chatter/lobes_input.hpp"

namespace lathectl::systems::b_chatter {

namespace {

using io::Param;
using io::Range;
using io::TableReader;
constexpr double kMm = 1e-3;  // mm → m
constexpr double kUm = 1e-6;  // µm → m
constexpr double kMs = 1e-3;  // ms → s

// [part]: the slender part between centres, a pinned-pinned beam.
void read_part(TableReader& root, RigConfig& b) {
  auto pt = root.table("part", true);
  pt->require({"length_mm", {0.0, 1e5, true, false}, "distance between the centres", kMm},
              b.part.length_m);
  pt->require({"diameter_mm", {0.0, 1e4, true, false}, "the part's diameter", kMm},
              b.part.diameter_m);
  pt->read({"youngs_modulus_GPa", {0.0, 1e4, true, false}, "E, Young's modulus of the part", 1e9},
           b.part.youngs_modulus_Pa);
  pt->read({"density_kg_per_m3", {0.0, 1e5, true, false}, "ρ, density of the part"},
           b.part.density_kg_per_m3);
  pt->require({"damping_ratio", {0.0, 1.0, true, true}, "ζ of each bending mode"},
              b.part.damping_ratio);
  pt->read({"modes", Range::closed(1, 6), "bending modes simulated"}, b.modes);
  pt->finish();
}

// [structure]: the tools' own structure from a machine file (`lathectl lobes`' format), in series
// with the part: its [[mode]]s and the modes fitted to its [[frf]]s, each tool its own copy.
void read_structure(TableReader& st, RigConfig& b) {
  st.document("machine_file",
              "a machine file of `lathectl lobes` (relative to this scenario) whose [[mode]]s and "
              "the modes fitted to its [[frf]]s are each tool's structure, fixed in space, in "
              "series with the part (its [part] is not used: the scenario's is the part; its "
              "K_f and speeds are the lobes')");
  b.tool_modes = read_structure_file(
      st, "machine_file", static_cast<std::size_t>(dynamics::TwinTurretCut::kMaxToolModes));
  st.finish();
}

// [cut]: the set-up and the NC program's one cutting block.
void read_cut(TableReader& root, RigConfig& b) {
  auto c = root.table("cut", true);
  const std::string setup =
      c->pick({"setup", {}, "one tool, or twin turrets dividing the feed or the depth"},
              {"single", "feed_division", "depth_division"});
  b.setup = setup == "single"          ? dynamics::TwinSetup::Single
            : setup == "feed_division" ? dynamics::TwinSetup::FeedDivision
                                       : dynamics::TwinSetup::DepthDivision;
  const auto depth = c->numbers(
      {"depth_mm", {0.0, 50.0, true, false}, "depth of cut [right, left]; one value means both"},
      1);
  c->check(depth.size() <= 2, "depth_mm", "one depth, or one per turret [right, left]");
  b.depth_mm[0] = depth[0];
  b.depth_mm[1] = depth.size() > 1 ? depth[1] : depth[0];
  c->require({"feed_mm_per_rev",
              {0.0, 10.0, true, false},
              "programmed feed; the feed rate of each turret is S = s·n"},
             b.feed_mm_per_rev);
  c->require(
      {"rpm", Range::closed(1.0, 1e5), "spindle speed; within the spindle's [min_rpm, max_rpm]"},
      b.rpm);
  c->read({"overlap", Range::closed(0, 1), "μ: overlap factor of a tool's own previous revolution"},
          b.overlap);
  c->read({"tool2_lag_mm", Range::closed(0, 1000),
           "axial lag of tool 2 behind tool 1 (not with a single tool)"},
          b.tool2_lag_mm);
  c->check(!(b.setup == dynamics::TwinSetup::Single && b.tool2_lag_mm > 0.0), "tool2_lag_mm",
           "a single-tool set-up has no second tool");
  c->require(
      {"z_start_mm", {0.0, 1e5, true, false}, "start of the cut, from the left (headstock) centre"},
      b.z_start_mm);
  c->require({"z_end_mm", {0.0, 1e5, true, false}, "end of the cut: z_start < z_end < length"},
             b.z_end_mm);
  c->check(b.z_end_mm > b.z_start_mm, "z_end_mm", "must exceed z_start_mm");
  c->check(b.z_end_mm < b.part.length_m / kMm, "z_end_mm",
           "must lie before the tailstock centre (part.length_mm)");
  c->read({"approach_mm", Range::closed(0, 100), "the tools start this far before z_start"},
          b.approach_mm);
  c->read({"idle_block_s", Range::closed(0, 100),
           "idle NC block before the cut (where compensator 13 stores the idle power)"},
          b.idle_block_s);
  c->read({"feed_drive_bandwidth_Hz", {0.0, 1e4, true, false}, "feed drives 3 and 6"},
          b.feed_drive_bandwidth_Hz);
  c->read({"initial_disturbance_um", Range::closed(0, 1000),
           "part displacement at the start of the cut"},
          b.initial_disturbance_um);
  const bool fixed =
      c->pick({"inter_tool_delay",
               {},
               "depth division: the pass of tool 1 whose surface tool 2 meets, found from both "
               "tools' axial positions at every step (the physics), or fixed at round(lag/s) + "
               "½ revolutions (the model before; a modulated feed cannot change it)"},
              {"axial_positions", "fixed"}, "axial_positions") == "fixed";
  b.inter_tool_delay =
      fixed ? dynamics::InterToolDelay::Fixed : dynamics::InterToolDelay::AxialPositions;
  const bool power =
      c->pick({"chip_law",
               {},
               "the force against the instantaneous depth the radial vibration changes: linear "
               "(Kienzle's b, the seed's model) or power, F(t0)·(t/t0)^(1−m) with the material's "
               "Kienzle m (nonlinear in the vibration: where quenching can act; "
               "docs/system-b-chatter.md)"},
              {"linear", "power"}, "linear") == "power";
  b.chip_law = power ? dynamics::ChipLaw::Power : dynamics::ChipLaw::Linear;
  c->finish();
}

// [vibration_sensor]: sensor 16, amplifier 17, setter 18, ADC 19, detector 20.
void read_vibration(TableReader& vs, sensors::VibrationChain::Params& v) {
  vs.read({"highpass_Hz", {0.0, 1e4, true, false}, "high-pass cut-off: the chatter band"},
          v.highpass_Hz);
  vs.read({"noise_um", Range::closed(0, 1000), "sensor noise σ per sample", kUm}, v.noise_m);
  vs.read({"dead_zone_um", Range::closed(0, 1e4), "setter 18: amplifier 17's dead zone", kUm},
          v.dead_zone_m);
  vs.read({"amplitude_gate_ms", {0.0, 1e5, true, false}, "ADC 19's peak-hold window", kMs},
          v.amplitude_gate_s);
  vs.read({"frequency_gate_ms", {0.0, 1e5, true, false}, "detector 20's counting window", kMs},
          v.frequency_gate_s);
  vs.read({"adc_lsb_um", {0.0, 1e3, true, false}, "ADC 19's resolution", kUm}, v.adc_lsb_m);
  vs.finish();
}

// [power_sensor]: sensor 11, switch 12, compensator 13, adder 14, ADC 15.
void read_power(TableReader& ps, sensors::PowerSensor::Params& pw,
                const drives::SpindleDrive::Params& spindle) {
  ps.read({"time_constant_ms", Range::closed(0, 1e4), "sensor 11's lag", kMs},
          pw.meter.time_constant_s);
  ps.read({"noise_W", Range::closed(0, 1e6), "sensor 11's noise σ"}, pw.meter.noise_sigma);
  ps.read({"adc_lsb_W", {0.0, 1e4, true, false}, "ADC 15's resolution"}, pw.adc_lsb_W);
  ps.read({"idle_average_ms",
           {0.0, 1e5, true, false},
           "compensator 13 averages the idle power over this window of the idle block",
           kMs},
          pw.idle_average_s);
  const std::string idle =
      ps.pick({"idle", {}, "idle power: stored at the idle block (seed), or a table over speed"},
              {"stored", "table"}, "stored");
  if (idle == "table" || ps.is_describing()) {
    // Beyond the seed: the idle law of the spindle tabulated at these speeds (measured on the
    // machine once, at commissioning).
    pw.idle_table_rpm = ps.numbers({"idle_table_rpm",
                                    {0.0, 1e5, true, false},
                                    "only with idle = \"table\": ascending speeds; the powers "
                                    "come from the spindle's idle law"},
                                   2);
    for (std::size_t i = 1; i < pw.idle_table_rpm.size(); ++i)
      ps.check(pw.idle_table_rpm[i] > pw.idle_table_rpm[i - 1], "idle_table_rpm",
               "speeds must ascend");
    pw.idle_table_W.clear();
    for (double n : pw.idle_table_rpm) pw.idle_table_W.push_back(drives::idle_power_W(spindle, n));
  }
  ps.finish();
}

// The module's defaults derived from the cut: F ∝ S^(1−m_p) and F_p/F_c from the Kienzle law at
// the programmed chip, and the part's modal mass at the middle of the cut.
void derive_module_defaults(const TableReader& root, RigConfig& b) {
  if (root.is_describing()) return;  // the reference shows the struct's, not a neutral cut's
  auto& m = b.module;
  const auto& fp = b.cutting.material.Fp;
  const auto& fc = b.cutting.material.Fc;
  const double h =
      b.setup == dynamics::TwinSetup::FeedDivision ? 0.5 * b.feed_mm_per_rev : b.feed_mm_per_rev;
  m.force_feed_exponent = 1.0 - fp.m;
  m.radial_force_ratio =
      fp.k11_N_per_mm2 * std::pow(h, 1.0 - fp.m) / (fc.k11_N_per_mm2 * std::pow(h, 1.0 - fc.m));
  m.part_mass_kg = part_modal_mass_kg(b.part, 0.5 * (b.z_start_mm + b.z_end_mm) * kMm);
}

// [modulation]: the CNC's modulated-feed module (or a programmed modulation).
void read_modulation(TableReader& md, RigConfig& b) {
  auto& m = b.module;
  const std::string src =
      md.pick({"source", {}, "who modulates the feed"}, {"automatic", "programmed", "none"});
  b.source = src == "automatic"    ? control::ModulationSource::Automatic
             : src == "programmed" ? control::ModulationSource::Programmed
                                   : control::ModulationSource::None;
  b.turret = md.pick({"turret", {}, "the turret the NC block flags for modulation"},
                     {"right", "left"}, "right") == "left"
                 ? control::Turret::Left
                 : control::Turret::Right;
  md.check(!(b.setup == dynamics::TwinSetup::Single && b.turret == control::Turret::Left), "turret",
           "a single-tool set-up has only the right turret");
  md.read({"coefficient", {0.0, 100.0, true, false},
           "the seed formula's number c (1.41); how it enters: coefficient_reading"},
          b.seed_coefficient);
  b.seed_divides =
      md.pick({"coefficient_reading",
               {},
               "the garbled seed formula read as A_P ≥ c·a0·m_d·|ω_d² − ω_m²| (multiply: a "
               "forced amplitude B ≥ 1.41·a0, twice van der Pol averaging's threshold) or A_P ≥ "
               "a0·m_d·|ω_d² − ω_m²|/c (divide: B ≥ a0/√2, the threshold itself)"},
              {"multiply", "divide"}, b.seed_divides ? "divide" : "multiply") == "divide";
  m.coefficient = b.module_coefficient();
  md.read({.key = "part_mass_kg",
           .range = {0.0, 1e6, true, false},
           .doc = "m_d; by default the first mode's modal mass at mid-cut",
           .derived = "the part's first modal mass at mid-cut"},
          m.part_mass_kg);
  md.read({.key = "radial_force_ratio",
           .range = {0.0, 10.0, true, false},
           .doc = "r; by default the Kienzle F_p/F_c at the programmed chip",
           .derived = "Kienzle F_p/F_c at the programmed chip"},
          m.radial_force_ratio);
  md.read({"force_feed_exponent",
           {0.0, 1.5, true, true},
           "e in F ∝ S^e; by default 1 − m of the Kienzle F_p law"},
          m.force_feed_exponent);
  md.read({"modulation_frequency_Hz", {0.0, 1e4, true, false}, "target ω_m/2π"},
          m.modulation_frequency_Hz);
  m.drive_bandwidth_Hz = b.feed_drive_bandwidth_Hz;
  md.read({"n_s", Range::closed(1, 1000), "steps from S_min to S_max"}, m.n_s);
  md.read({"resolution_um",
           {0.0, 1e4, true, false},
           "the control's resolution; Δl is a multiple of it",
           kUm / kMm},
          m.resolution_mm);
  md.read({"s_min_fraction", {0.0, 1.0, true, true}, "S_min ≥ this · S_p"}, m.s_min_fraction);
  md.read({"s_max_fraction", {1.0, 100.0, true, false}, "S_max ≤ this · S_p"}, m.s_max_fraction);
  md.read({"engage_time_ms", Range::closed(0, 1e5), "a0 > 0 for this long before engaging", kMs},
          m.engage_time_s);
  md.read({"replan_period_s", {0.0, 1e4, true, false}, "the plan is renewed this often"},
          m.replan_period_s);
  md.read({"release_below_dead_zone", {}, "true: the seed's literal rule (release below it)"},
          m.release_below_dead_zone);
  md.read({"release_time_ms", Range::closed(0, 1e5),
           "a0 below the dead zone for this long before releasing", kMs},
          m.release_time_s);
  md.read({"desync_fraction", Range::closed(0, 100),
           "> 0: lengthen Δl until the turrets' offset swings by ≥ this·s"},
          m.desync_fraction);
  if (b.source == control::ModulationSource::Programmed || md.is_describing()) {
    auto& pr = b.programmed;
    md.require({"S_min_mm_per_min", {0.0, 1e5, true, false}, "programmed only: S_min"},
               pr.s_min_mm_per_min);
    md.require(
        {"dS_mm_per_min", {0.0, 1e5, true, false}, "programmed only: ΔS, a multiple of 0.1 mm/min"},
        pr.ds_mm_per_min);
    md.check(!(std::abs(std::remainder(pr.ds_mm_per_min, 0.1)) > 1e-9), "dS_mm_per_min",
             "must be a multiple of 0.1 mm/min (the seed's feed quantum)");
    md.require(
        {"dl_mm", {0.0, 1e4, true, false}, "programmed only: Δl, a multiple of resolution_um"},
        pr.dl_mm);
    const double units = pr.dl_mm / m.resolution_mm;
    md.check(!(std::abs(units - std::round(units)) > 1e-6), "dl_mm",
             "must be a multiple of the resolution (modulation.resolution_um)");
    pr.n_s = m.n_s;
  }
  md.finish();
}

// [process_damping]: the flank ploughing the surface it has just cut (beyond the seed).
void read_process_damping(TableReader& pd, RigConfig& b) {
  auto& p = b.process_damping;
  p.enabled = pd.pick({"model", {}, "none, or the flank's indentation (Wu 1989; Chiou & "
                                       "Liang 1998): a radial force K_sp·w·A of the area A the "
                                       "flank overlaps the surface"},
                      {"none", "indentation"}, p.enabled ? "indentation" : "none") ==
              "indentation";
  pd.read({"K_sp_N_per_mm3", {0.0, 1e7, true, false},
           "K_sp, the specific indentation force (steels: order 1e4 … 1e5 N/mm³)", 1e9},
          p.k_sp_N_per_m3);
  pd.read({"wear_land_mm", Range::closed(0, 2), "VB, the flank's wear land (no clearance)"},
          p.wear_land_mm);
  pd.read({"clearance_deg", {0.0, 45.0, true, true}, "γ, the clearance beyond the land"},
          p.clearance_deg);
  pd.read({"flank_length_mm", {0.0, 20.0, true, false},
           "how far behind the edge the flank reaches (the insert's thickness)"},
          p.flank_length_mm);
  pd.finish();
}

// [study]: what the study runs besides the scenario itself.
void read_study(TableReader& st, Settings& s) {
  st.read({"compare_without_modulation", {}, "also run without modulation"}, s.compare);
  s.sweep_feed_mm_per_rev =
      st.numbers({"sweep_feed_mm_per_rev",
                  {0.0, 10.0, true, false},
                  "feeds at which to run with and without modulation (at most 40)"});
  st.check(s.sweep_feed_mm_per_rev.size() <= 40, "sweep_feed_mm_per_rev", "at most 40 feeds");
  st.finish();
}

void read_tables(TableReader& root, io::Scenario& sc, const io::MaterialLibrary& lib, Settings& s) {
  auto& b = s.rig;
  read_part(root, b);
  if (auto st = root.table("structure")) read_structure(*st, b);
  // The regenerative gain is dF/db at the chip: the Kienzle form (handbook laws have t^x, x ≠ 1).
  io::read_material_tool(root, lib, b.cutting, nullptr, true);
  read_cut(root, b);
  root.check(
      !((b.z_end_mm - b.z_start_mm) / (b.feed_mm_per_rev * b.rpm / 60.0) > sc.run.duration_s),
      "run", "run.duration_s is shorter than the cut (z_end − z_start at feed·rpm)");

  if (auto sp = root.table("spindle")) io::read_spindle(*sp, b.spindle, true);
  root.check(b.rpm >= b.spindle.min_rpm && b.rpm <= b.spindle.max_rpm, "cut",
             "cut.rpm must lie within the spindle's [min_rpm, max_rpm]");

  if (auto vs = root.table("vibration_sensor")) read_vibration(*vs, b.vibration);
  b.vibration.seed = static_cast<unsigned>(sc.run.seed ^ 0x5EED01ULL);
  b.power.meter.seed = sc.run.seed ^ 0xB0B0B0B0ULL;
  if (auto ps = root.table("power_sensor")) read_power(*ps, b.power, b.spindle);

  derive_module_defaults(root, b);
  if (auto md = root.table("modulation")) read_modulation(*md, b);
  if (auto pd = root.table("process_damping")) read_process_damping(*pd, b);
  if (auto st = root.table("study")) read_study(*st, s);
}

}  // namespace

const std::array<io::CriterionKey, 2> kAcceptanceKeys{{
    {"max_vibration_um", "steady vibration amplitude of the part", false,
     std::numeric_limits<double>::quiet_NaN(), Range::closed(0, 1e5),
     "largest steady vibration amplitude of the part over the last 30 % of the cut (with the "
     "scenario's modulation, if any), µm (default: vibration_sensor.dead_zone_um, the vibration "
     "the machine's setter 18 tolerates; 0: not judged)"},
    {"min_mean_feed_pct", "mean feed of the modulated turret, % of programmed", true, 90.0,
     Range::closed(0, 1000),
     "smallest mean feed of the modulated turret against the programmed feed, %: the "
     "productivity the modulation may cost (default 90; judged only with modulation)"},
}};

std::unique_ptr<io::SystemSettings> read_settings(TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib) {
  auto s = std::make_unique<Settings>();
  try {
    read_tables(root, sc, lib, *s);
  } catch (const std::invalid_argument& e) {  // the part's beam model refuses it
    io::throw_at_key(sc, e, "part");
  }
  // The derived default is set before the read, so the run's settings show the value used.
  if (!root.is_describing())
    s->acceptance.set_default("max_vibration_um", s->rig.vibration.dead_zone_m * 1e6);
  io::read_acceptance(root, s->acceptance);
  return s;
}

}  // namespace lathectl::systems::b_chatter
