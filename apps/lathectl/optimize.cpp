// `lathectl optimize PROGRAM.ngc SCENARIO.toml --out DIR [--verify]`: offline feed optimisation
// of a turning NC program on a system-E scenario's blank, read by LinuxCNC's own interpreter and
// optionally verified in LinuxCNC's simulated lathe (src/optimize/optimize.hpp).
#include "optimize/optimize.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/install_paths.hpp"
#include "lathectl/io/linuxcnc_ini.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/study.hpp"
#include "systems/registry.hpp"

namespace fs = std::filesystem;

namespace lathectl::cli {
namespace {


struct Args {
  std::string program, scenario, out = "optimize-out", sim, rs274 = "rs274", tool_file, ini;
  bool verify = false;
  double timeout_s = 1800.0;
  optimize::Options opt;
};

// The simulated lathe's configuration (its INI and tool table): the sources' hal/config, or the
// installed share/lathectl/hal/config; $LATHECTL_HAL_CONFIG_DIR over both.
std::string hal_config_dir() {
  return io::locate_tree(
      "LATHECTL_HAL_CONFIG_DIR",
      {LATHECTL_SOURCE_HAL_CONFIG, LATHECTL_HAL_CONFIG_SUBDIR, LATHECTL_INSTALLED_HAL_CONFIG},
      "lathectl-lathe.ini");
}

int run(Args& a) {
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = systems::load_scenario(a.scenario, lib);
  if (sc.system != "E")
    throw io::InputError(a.scenario + ": a system-" + sc.system +
                         " scenario; lathectl optimize needs a system-E scenario (material, "
                         "tool, blank, force limit and feed bounds)");
  const auto& e = sc.get<systems::e_adaptive::Settings>();
  if (e.rig.stock.blank_diameter_mm.size() < 2)
    throw io::InputError(a.scenario +
                         ": key 'stock.blank': lathectl optimize needs the blank's "
                         "extent along z (at least two points)");
  // The machine: the user's INI (--ini) or the simulated lathe's, read on the checked path; its
  // units, soft limits, velocity, acceleration and tool table ([EMCIO]TOOL_TABLE beside it,
  // unless --tool-table).
  a.opt.ini = a.ini.empty() ? (fs::path(hal_config_dir()) / "lathectl-lathe.ini").string() : a.ini;
  const auto machine = io::lathe_machine(io::parse_linuxcnc_ini(
      io::read_input_file(a.opt.ini, "a LinuxCNC INI file (--ini)", io::kMaxTomlBytes), a.opt.ini));
  const bool own_table = !a.ini.empty() || !a.opt.tool_table.empty();  // not the sim's own
  if (a.opt.tool_table.empty()) a.opt.tool_table = optimize::machine_tool_table(a.opt.ini, machine);
  if (machine.max_acceleration_mm_s2) a.opt.machine.accel_mm_s2 = *machine.max_acceleration_mm_s2;
  if (machine.max_velocity_mm_s) a.opt.machine.vmax_mm_s = *machine.max_velocity_mm_s;
  // The machine's tool table: each tool's orientation Q (where its programmed point is on the
  // nose, as LinuxCNC moves it) and, with a tool file, its nose (D) and angles.
  auto table = optimize::read_tool_table(
      io::read_input_file(a.opt.tool_table, "a LinuxCNC tool table (--tool-table)",
                          io::kMaxTomlBytes),
      a.opt.tool_table);
  for (auto& t : table) t.diameter_mm *= machine.unit_mm;  // an inch machine's table: inches
  if (!a.tool_file.empty()) {
    // The tool file says what LinuxCNC's tool table cannot (kind, insert width, feed range);
    // the table gives each tool's nose (D) and angles, and the two must agree.
    a.opt.tool_specs = optimize::read_tool_file(
        io::read_input_file(a.tool_file, "a tool file", io::kMaxTomlBytes), a.tool_file);
    optimize::apply_tool_table(a.opt.tool_specs, table, a.tool_file, a.opt.tool_table);
  }
  a.opt.table_tools = std::move(table);
  // The user's machine starts the program where its homing leaves the tool, when that is clear
  // of the blank (optimize::machine_start); --verify's simulated lathe homes there too.
  if (!a.ini.empty()) {
    const auto start = optimize::machine_start(machine, a.opt.ini, e, a.opt);
    a.opt.start_x_mm = start.x_mm;
    a.opt.start_z_mm = start.z_mm;
    if (!start.from_ini) std::cout << "note: " << start.note << "\n";
  }
  a.opt.rs274 = a.rs274;
  a.opt.label = a.program;
  const auto prog = optimize::read_program(a.program, a.opt);
  const auto result = optimize::optimize(prog, e, a.opt);
  bool touched = false;
  for (double d : result.before.s.depth) touched = touched || d > 0.0;
  if (!touched)
    throw io::InputError(a.program + ": the tool never touches the blank of " + a.scenario +
                         " (its face is at machine Z " + io::fmt(a.opt.z_origin_mm) +
                         ", the part toward -Z; --z-origin-mm Z places it)");
  io::prepare_output_dir(a.out, "--out", true,  // before --verify's runs, not after them
                         {a.program, a.scenario, a.tool_file, a.opt.tool_table});
  std::unique_ptr<optimize::Verified> v;
  if (a.verify) {
    optimize::VerifyOptions vo;
    std::string sim = a.sim;
    if (sim.empty()) {
      const fs::path src =
          fs::path(LATHECTL_SOURCE_HAL_CONFIG) / ".." / ".." / "scripts" / "linuxcnc-sim";
      sim = fs::exists(src) && hal_config_dir() == LATHECTL_SOURCE_HAL_CONFIG
                ? src.lexically_normal().string()
                : "lathectl-linuxcnc-sim";
    }
    std::istringstream words(sim);
    for (std::string w; words >> w;) vo.sim.push_back(w);
    vo.scenario = fs::absolute(a.scenario).string();
    vo.timeout_s = a.timeout_s;
    if (!a.tool_file.empty()) vo.tool_file = fs::absolute(a.tool_file).string();
    if (!a.ini.empty()) vo.machine = machine;
    if (own_table)  // the simulated lathe cuts with the tools the prediction took
      vo.tool_table_text =
          io::read_input_file(a.opt.tool_table, "a LinuxCNC tool table", io::kMaxTomlBytes);
    v = std::make_unique<optimize::Verified>(optimize::verify(prog, result, a.opt, vo));
  }
  io::write_output_set(a.out, optimize::output_files(prog, result, e, a.opt, a.scenario, v.get()));
  std::cout << a.program << ": predicted cycle " << result.before.cycle_time_s << " s → "
            << result.after.cycle_time_s << " s, " << result.blocks_changed << " lines changed";
  if (v)
    std::cout << "; LinuxCNC " << v->runs[0].cycle_time_s << " s → " << v->runs[1].cycle_time_s
              << " s, force peak " << v->runs[0].force_peak_rev << " → "
              << v->runs[1].force_peak_rev << " (limit " << result.limit << "), prediction error "
              << v->prediction_error_pct << " % of the limit";
  std::cout << "\n  → " << (fs::path(a.out) / "optimized.ngc").string() << "\n";
  if (result.before.blend_inside_max_mm > 0.01)
    std::cout << "  note: " << optimize::blend_note(result.before) << "\n";
  for (const auto& w : optimize::warnings(prog, e, result))
    std::cout << "WARNING: " << a.program << ": " << w << "\n";
  return 0;
}

}  // namespace

void add_optimize(CLI::App& app, Commands& out) {
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "optimize",
      "Optimise the feeds of a turning NC program on a system-E scenario's blank (read by "
      "LinuxCNC's interpreter; --verify runs it in LinuxCNC's simulated lathe)");
  sub->add_option("program", a->program, "NC program (.ngc)")->required();
  sub->add_option("scenario", a->scenario,
                  "system-E scenario (TOML): material, tool, blank, limits")
      ->required();
  sub->add_option("--out", a->out, "output directory")->capture_default_str();
  sub->add_flag("--verify", a->verify,
                "run the original and the optimised program in LinuxCNC (adaptive control off, "
                "then on) and report both");
  sub->add_option("--spindle-rpm", a->opt.spindle_rpm,
                  "start the spindle at this speed before the program (as linuxcnc-sim)")
      ->check(range_validator(io::Range::closed(0.0, 1e5)));
  sub->add_option("--z-origin-mm", a->opt.z_origin_mm,
                  "machine Z of the stock's face (as linuxcnc-sim)")
      ->check(range_validator(io::Range::any()))
      ->capture_default_str();
  sub->add_option("--air-feed", a->opt.air_feed,
                  "feed in air [mm/rev] (default: the scenario's controller.feed_max_mm_per_rev)")
      ->check(range_validator(io::Range::closed(1e-3, 10.0)));
  sub->add_option("--finish-depth-mm", a->opt.finish_depth_mm,
                  "pieces at most this deep are finishing: their feed keeps the roughness")
      ->check(range_validator(io::Range::closed(0.0, 10.0)))
      ->capture_default_str();
  sub->add_option("--finish-ra-um", a->opt.finish_ra_um,
                  "roughness Ra of finishing pieces (default: the programmed feed's, "
                  "Ra = f²/(32 r); never rougher than it)")
      ->check(range_validator(io::Range::closed(0.01, 100.0)));
  a->opt.finish_ra_um = 0.0;
  sub->add_option("--limit-fraction", a->opt.limit_fraction,
                  "share of each limit the chosen feed predicts")
      ->check(range_validator(io::Range::closed(0.5, 1.0)))
      ->capture_default_str();
  sub->add_option("--rs274", a->rs274, "LinuxCNC's standalone interpreter")->capture_default_str();
  sub->add_option(
      "--sim", a->sim,
      "the simulator command for --verify (default scripts/linuxcnc-sim, installed "
      "lathectl-linuxcnc-sim); words split at blanks, e.g. \"flock LOCK linuxcnc-sim\"");
  sub->add_option("--timeout", a->timeout_s, "--verify: time limit of each LinuxCNC run [s]")
      ->check(range_validator(io::Range::closed(1.0, 1e5)))
      ->capture_default_str();
  sub->add_option("--interp-timeout", a->opt.interp_timeout_s,
                  "time limit of LinuxCNC's interpreter reading the program [s] (an endless "
                  "o-word loop is stopped with an error)")
      ->check(range_validator(io::Range::closed(1.0, 1e5)))
      ->capture_default_str();
  sub->add_option("--tools", a->opt.tools,
                  "the T numbers the scenario's [tool] describes, e.g. 1,3 (default: the tool of "
                  "the first feed move); feed moves of other tools keep their feeds")
      ->delimiter(',')
      ->check(CLI::Range(0, 99999));
  sub->add_option("--tool-file", a->tool_file,
                  "the program's other tools by T number: kind, insert width, feed range (TOML, "
                  "docs/optimize.md)");
  sub->add_option("--ini", a->ini,
                  "the machine's LinuxCNC INI: its units, X and Z soft limits, velocity, "
                  "acceleration and tool table ([EMCIO]TOOL_TABLE) (default: the simulated "
                  "lathe's lathectl-lathe.ini)");
  sub->add_option("--tool-table", a->opt.tool_table,
                  "LinuxCNC's tool table (.tbl) the interpreter and the tools' noses (D) and "
                  "angles (I, J, Q) come from (default: the INI's [EMCIO]TOOL_TABLE)");
  sub->add_flag("--allow-rapid-in-material", a->opt.allow_rapid_in_material,
                "optimise a program whose rapid (G0) passes through the blank (an error "
                "otherwise); the lines from that rapid on keep their feeds");
  sub->footer("Lines marked (lathectl:keep), threading (G33/G76) and the feed moves of tools "
              "other than the scenario's keep their feeds; finishing cuts (cutter compensation, "
              "G70, (lathectl:finish), a pass mostly within --finish-depth-mm) are never raised. " +
              doc("optimize.md") + ".");
  out.push_back({sub, [a] { return run(*a); }});
}

}  // namespace lathectl::cli
