// `lathectl report DIR` of system B's session on the twin-turret lathe
// (scripts/linuxcnc-sim-twin --out DIR): the registry's session report for system B (entry.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/format.hpp"
#include "lathectl/io/json_file.hpp"
#include "lathectl/io/operation_log.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "systems/b_chatter/entry.hpp"

namespace lathectl::systems::b_chatter {
namespace {

namespace fs = std::filesystem;
using io::fixed;

// System B's session on the twin-turret lathe (scripts/linuxcnc-sim-twin): summary.json's measures
// (null where the session did not reach them) and the recording's channels.
// The recording's channels: the vibration at the tool, the turrets' feeds and W's external
// offset over time, with `marks`; the number of servo periods recorded.
std::size_t add_recording_plots(io::Report& r, const fs::path& csv,
                                const std::vector<io::Marker>& marks) {
  const io::ChannelTable table = io::read_channels_csv(csv);
  auto col = [&](const char* name) -> const std::vector<double>& {
    for (std::size_t i = 0; i < table.names.size(); ++i)
      if (table.names[i] == name) return table.columns[i];
    throw io::InputError(csv.string() + ": no column " + name + " (not linuxcnc-sim-twin's)");
  };
  const auto &t = col("time_s"), &peak = col("vibration_peak_um"), &a0 = col("a0_um");
  const auto &z = col("z_mm"), &w = col("w_mm"), &level = col("feed_mm_per_min");
  const auto &eo = col("w_eoffset_mm"), &motion = col("motion_type"), &on = col("module_on");
  r.plots.push_back({"Vibration at the tool",
                     "time [s]",
                     "amplitude [µm]",
                     {{"peak of the high-passed displacement", t, peak, "", false, false},
                      {"a0 (ADC 19, 0 below the dead zone)", t, a0, "", true, false}},
                     marks});
  // The turrets' speeds from the recorded joints (one servo period apart), in feed moves.
  std::vector<double> vz(t.size(), 0.0), vw(t.size(), 0.0), s_level(t.size(), 0.0);
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double dt = t[i] - t[i - 1];
    if (dt <= 0.0 || (motion[i] != 2.0 && motion[i] != 3.0)) continue;
    s_level[i] = on[i] != 0.0 ? level[i] : 0.0;
    vz[i] = std::abs(z[i] - z[i - 1]) / dt * 60.0;
    vw[i] = std::abs(w[i] - w[i - 1]) / dt * 60.0;
  }
  r.plots.push_back({"The turrets' feeds",
                     "time [s]",
                     "feed [mm/min]",
                     {{"right turret (W)", t, vw, "", false, false},
                      {"left turret (Z)", t, vz, "", false, false},
                      {"the module's level S(t) (while on)", t, s_level, "", true, false}},
                     marks});
  r.plots.push_back({"W's external offset (axis.w.eoffset)",
                     "time [s]",
                     "offset [mm]",
                     {{"offset", t, eo, "", false, false}},
                     marks});
  return t.size();
}

int twin_session_report(const fs::path& dir, const std::string& out_arg) {
  const fs::path summary = dir / "summary.json", csv = dir / "signals.csv";
  const fs::path out = out_arg.empty() ? dir / "report.html" : fs::path(out_arg);
  io::check_output_file(out, "--out", {summary, csv});
  const io::JsonFile f = io::JsonFile::read(summary, "the session's summary");
  const auto& doc = f.doc();
  if (!doc.is_object()) f.fail("", "expected the session's summary (an object)");
  // A measure the session reached, else "—": `path` is dotted, its numbers checked.
  const auto val = [&](const std::string& path, double scale, int digits) -> std::string {
    const nlohmann::json* v = &doc;
    std::string key;
    std::size_t a = 0;
    while (a <= path.size()) {
      const std::size_t b = std::min(path.find('.', a), path.size());
      const std::string name = path.substr(a, b - a);
      if (!v->is_object() || !v->contains(name) || (*v)[name].is_null()) return "—";
      if (b == path.size()) return fixed(scale * f.number(*v, key, name.c_str()), digits);
      key += (key.empty() ? "" : ".") + name;
      v = &(*v)[name];
      a = b + 1;
    }
    return "—";
  };
  io::Report r;
  r.title = "System B on LinuxCNC — the twin-turret lathe";
  r.subtitle = (doc.contains("program") && doc["program"].is_string()
                    ? doc["program"].get<std::string>() + " · "
                    : std::string()) +
               summary.string();
  r.description =
      "The left turret on X/Z, the right one on U/W, one program for both; lathectl_chatter cuts "
      "the slender part with both tools and lathectl_modfeed modulates the flagged turret's feed "
      "through LinuxCNC's external axis offset on its axial axis. Amplitudes are rig B's measure "
      "(the peak of the high-passed displacement at the tool).";
  r.doc_page = "linuxcnc.md";
  r.metrics = {
      {"module engaged after contact [s]", val("modulation.engaged_after_contact_s", 1, 3)},
      {"plan S_min / ΔS [mm/min]",
       val("modulation.S_min_mm_per_min", 1, 1) + " / " + val("modulation.dS_mm_per_min", 1, 1)},
      {"plan Δl [mm] / n_s", val("modulation.dl_mm", 1, 3) + " / " + val("modulation.n_s", 1, 0)},
      {"chatter frequency (detector 20) [Hz]", val("chatter_frequency_Hz", 1, 1)},
      {"amplitude with the module, 2–3 s after engaging [µm]",
       val("vibration_amplitude_um.with", 1, 2)},
      {"amplitude without (the module off, the cut's end) [µm]",
       val("vibration_amplitude_um.without", 1, 2)},
      {"growth rate before engaging / module off [1/s]",
       val("growth_rate_per_s.before_engaging", 1, 3) + " / " +
           val("growth_rate_per_s.module_off", 1, 3)},
      {"mean feed programmed / left / right [mm/min]",
       val("mean_feed_mm_per_min.programmed", 1, 2) + " / " +
           val("mean_feed_mm_per_min.left", 1, 2) + " / " +
           val("mean_feed_mm_per_min.right", 1, 2)},
      {"left turret off the right one's plan, largest [µm]",
       val("left_turret_max_gap_to_plan_mm", 1e3, 3)},
      {"feed step → axis speed, median / longest [ms]",
       val("eoffset.latency_ms.median", 1, 0) + " / " + val("eoffset.latency_ms.max", 1, 0)},
      {"offset, largest / after the program [mm]",
       val("eoffset.max_abs_mm", 1, 4) + " / " + val("eoffset.at_end_mm", 1, 6)},
      {"override: factor / left turret [mm/min]",
       val("override.factor", 1, 3) + " / " + val("override.left_mm_per_min", 1, 2)},
      {"programmed variant: the named turret on its level [share]",
       val("programmed.left_on_level_share", 1, 3)}};
  std::vector<io::Marker> marks;
  for (const auto& [key, label] : {std::pair{"contact_at_s", "contact"},
                                   {"modulation.engaged_at_s", "engaged"},
                                   {"cut_end_s", "the cut's end"}}) {
    const std::string v = val(key, 1, 3);
    if (v != "—") marks.push_back({std::stod(v), label});
  }
  const std::size_t periods = add_recording_plots(r, csv, marks);
  io::write_output_file(out, io::render_html(r), "--out", {summary, csv});
  std::cout << "system B session: " << periods << " servo periods → " << out.string() << "\n";
  return 0;
}

}  // namespace

// scripts/linuxcnc-sim-twin's directory (or its summary.json), no operation log.
bool is_session(const fs::path& path) {
  return io::is_runner_output(path, {"signals.csv", "report.txt"});
}

int session_report(const fs::path& path, const std::string& out) {
  return twin_session_report(fs::is_directory(path) ? path : path.parent_path(), out);
}

}  // namespace lathectl::systems::b_chatter
