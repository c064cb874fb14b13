#pragma once
// `lathectl lobes MACHINE.toml --out DIR`: stability lobes of a machine's chatter model (system
// B's), by the frequency domain and, independently, by semi-discretization (limit depths at
// sd_speeds speeds by bisection, and a speed × depth chart of the SD map's unstable roots);
// writes lobes.json, lobes.csv and lobes.html. The machine file — [cutting], [[mode]] and/or [part] (a slender part
// between centres, dynamics/beam.hpp), [speed], optional [lobes] — is read in lobes_input.cpp,
// where each key is described once (describe_machine_file; docs/machine-file-reference.md).

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {
class Progress;
}  // namespace lathectl::io

namespace lathectl::systems::b_chatter {

// Ranges the machine file keeps to beyond each key's own (docs/machine-file-reference.md,
// "Ranges and cost"), each where the model stops meaning anything or the work stops being bounded:
inline constexpr double kCentreMargin = 0.01;     // positions ≥ 1 % of the length from a centre
inline constexpr std::size_t kMaxPositions = 1000;  // positions_mm entries (a lobe set each)
inline constexpr double kMaxModeHz = 1e6;         // the part's highest mode, as [[mode]]'s bound
inline constexpr double kMinLimitDepth_m = 1e-12;  // each mode's SDOF limit 2kζ(1+ζ)/(K_f·cos²θ)
inline constexpr int kMaxLobes = 5000;            // lobes down to min_rpm (and max_lobes)
inline constexpr double kMaxBytes = 2.0 * 1024 * 1024 * 1024;  // estimated peak memory
inline constexpr double kMaxSeconds = 3600.0;     // estimated time on this machine's threads

struct LobesPart {
  dynamics::BeamPart beam;
  int modes = 3;
  double position_m = 0.25;         // cutting position (from the headstock centre)
  std::vector<double> positions_m;  // critical depth along the part at these positions
};

struct LobesInput {
  dynamics::ChatterSystem system;          // every mode at the cutting position
  std::vector<dynamics::Mode> tool_modes;  // the [[mode]]s alone
  std::optional<LobesPart> part;
  double min_rpm = 1000.0, max_rpm = 10000.0;
  int max_lobes = 40;  // set by the reader: [lobes] max_lobes, or lobes_needed()
  int sd_speeds = 40;
  int chart_speeds = 200, chart_depths = 100;
  double chart_max_depth_m = 0.0;  // 0: 4 × the absolute limit
  int chart_steps_per_period = 7;
};

LobesInput load_lobes_input(const std::string& path);  // throws InputError
// The same from text (file_label names it in error messages); throws InputError.
LobesInput parse_lobes_input(std::string_view text, const std::string& file_label);
// The machine file's keys, with their ranges, defaults and meaning (the reader run without a file).
io::ParamLog describe_machine_file();
// The modes seen at the tool with the cutting position at x_m: the part's plus the tool's.
dynamics::ChatterSystem lobes_system_at(const LobesInput& in, double x_m);
// The lobes N = 0, 1, ... needed for the frequency-domain envelope to reach min_rpm: lobe N lies
// near 60·f_c/(N + ε/2π), so N up to ⌈60·f_c/min_rpm⌉ (+ 2 for the phase ε and the lobes' width),
// f_c = f_n·√(1+2ζ) of the highest mode that can chatter — one whose SDOF limit is within 3× the
// lowest mode's (a stiff mode far above cannot lower the envelope), at every position.
int lobes_needed(const LobesInput& in);  // saturates at INT_MAX/2 (the reader: ≤ kMaxLobes)
double lobes_needed_count(const LobesInput& in);  // the same as a double, never overflowing
// f_c above, the highest over the part's positions.
double lobes_reference_Hz(const LobesInput& in);

// What run_lobes will cost, estimated before anything is allocated (lobes.cpp says how):
// the frequency-domain lobe points (their memory), the semi-discretization cells (each a root
// count of ~4·m samples, m the steps per revolution), peak memory and time on `threads` threads.
struct LobesCost {
  double fd_points = 0.0;       // lobe points of the largest frequency-domain set (held at once)
  double fd_point_visits = 0.0;  // over every set (the cutting position's and each position's)
  double sd_cells = 0.0;        // bisection cells (sd_speeds)
  double chart_cells = 0.0;     // chart cells, with the boundary bisection
  int max_steps = 0;            // the largest m of the chart and the bisection
  double cell_seconds = 0.0;    // Σ over cells of the modelled time of one (one thread)
  double fd_seconds = 0.0;
  double bytes = 0.0;           // estimated peak memory
  double fd_bytes = 0.0, chart_bytes = 0.0, sd_bytes = 0.0;
  unsigned threads = 1;
  double seconds = 0.0;  // estimated wall time: fd_seconds + cell_seconds / threads
};
LobesCost lobes_cost(const LobesInput& in, unsigned threads = 0);  // 0: hardware threads
// Computes and writes the outputs; returns lobes.json's content, with "warnings" (speeds where
// no lobe reaches, lobes whose minimum lies outside the speed range). progress: optional.
nlohmann::json run_lobes(const LobesInput& in, const std::filesystem::path& out_dir,
                         io::Progress* progress = nullptr);

}  // namespace lathectl::systems::b_chatter
