#pragma once
// The machine file of `lathectl lobes` and of a scenario's [structure] machine_file (system B):
// its types, its reader (lobes_input.cpp, each key described once: describe_machine_file;
// docs/machine-file-reference.md), the structure it gives at the tool (lobes_system.cpp) and
// what the lobes would cost (lobes_cost.cpp). In the settings library: a scenario's machine file
// is read with the scenario, by the HAL component too. What `lathectl lobes` computes from it is
// lobes.hpp.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/frf.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "lathectl/io/toml_reader.hpp"

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

// Frequency grid of the lobes, 0.5·f_min..2·f_max: dense lobes (a slender part at low speed, a
// stiff tool mode far above) need ~0.1 Hz near each mode, or the envelope overshoots at the
// lobe crossings by tens of per cent (measured on examples/machines/b_part.toml).
inline constexpr int kFrequencyPoints = 40000;

struct LobesPart {
  dynamics::BeamPart beam;
  std::string support = "centres";  // "centres", "chuck", "chuck_tailstock"
  dynamics::BeamSupports supports;   // the same, and the steady rest
  // The finite-element model of any set-up but plain centres (which keeps the analytic beam).
  std::shared_ptr<const dynamics::BeamModel> model;
  int modes = 3;
  double position_m = 0.25;         // cutting position (from the headstock centre)
  std::vector<double> positions_m;  // critical depth along the part at these positions
};

// What `lobes --recommend` (and the report's first section) needs beyond the lobes: the cut's
// feed, diameter and tangential force coefficient for the spindle's power P = F_c·v and torque
// T = F_c·D/2 with F_c = k_c·b·h, and the machine's limits on them.
struct LobesRecommend {
  double feed_m = 0.1e-3;         // [cutting] feed_mm_per_rev: the chip thickness h
  double kc_N_per_m2 = 0.0;       // [cutting] kc_N_per_mm2; 0: K_f
  double diameter_m = 0.0;        // [cutting] diameter_mm; 0: the part's, else kDefaultDiameter
  double power_W = 0.0;           // [machine] power_kW; 0: no limit
  double torque_Nm = 0.0;         // [machine] torque_Nm; 0: no limit
  double safety_factor = 1.25;    // [recommend]: the depth is the stability limit / this
  int pockets = 3;                // [recommend]: how many of the best pockets are listed
};
inline constexpr double kDefaultDiameter_m = 0.05;

// One [[frf]] table: a measured FRF file and how it enters the chip-thickness direction.
struct LobesFrf {
  std::string file;       // as the machine file writes it
  std::string path;       // as read: relative to the machine file's folder
  std::string direction;  // "x", "y", "xy", "yx"
  std::string of;         // "tool", "part"
  double weight = 1.0;    // its share of the oriented FRF: cos²α, sin²α or cosα·sinα (×2 for
                          // a cross term whose reciprocal is not given)
  dynamics::Frf frf;      // receptance as read [m/N]
  std::vector<std::string> notes;  // what the reader skipped (a 0 Hz row): lobes.json's warnings
};

// The measured side of the machine: the oriented sum of the [[frf]]s, as measured, fitted with
// modes for everything that needs modes, and what the frequency-domain lobes read: the FRF
// against its fit (dynamics::smooth_against_fit: the fit plus the residual smoothed) when the
// sharpest peak is sampled finely enough (dynamics::kMinSamplesPerBandwidth); coarser, the
// residual's window is dynamics::kCoarseWindowFactor times wider (read_directly false: the
// lobes then read the fit and only the residual's slow part, and the report says so).
struct LobesMeasured {
  dynamics::Frf oriented;  // Σ weight·FRF on the first file's grid, where every file is measured
  dynamics::Frf smoothed;  // what the frequency domain reads: the FRF against its fit
  double smoothing_half_window_Hz = 0.0;  // of the residual from the fit
  double samples_per_bandwidth = 0.0;  // across the sharpest fitted peak's half-power band
  bool read_directly = true;           // false: sampled too coarsely, the window widened
  dynamics::FrfFit fit;
};

struct LobesInput {
  dynamics::ChatterSystem system;          // every mode at the cutting position, and the
                                           // measured FRF (frequency domain)
  dynamics::ChatterSystem modal;           // the same with the FRF replaced by its fitted modes
  std::vector<dynamics::Mode> tool_modes;  // the [[mode]]s alone
  std::vector<LobesFrf> frfs;              // the [[frf]]s
  std::optional<LobesMeasured> measured;   // when there are [[frf]]s
  double chip_direction_rad = 0.0;         // [cutting] chip_direction_deg: from x towards y
  std::optional<LobesPart> part;
  double min_rpm = 1000.0, max_rpm = 10000.0;
  int max_lobes = 40;  // set by the reader: [lobes] max_lobes, or lobes_needed()
  int sd_speeds = 40;
  int chart_speeds = 200, chart_depths = 100;
  double chart_max_depth_m = 0.0;  // 0: 4 × the absolute limit
  int chart_steps_per_period = 7;
  LobesRecommend recommend;
  // [process_damping]: C of dynamics::ChatterSystem (c = C·b/n), 0 without the table; the
  // frequency-domain lobes take it, semi-discretization cannot (no SD limits or chart then).
  double process_damping_C = 0.0;
  double process_damping_k_sp_N_per_m3 = 4e13, process_damping_vb_m = 0.1e-3;
  double process_damping_kappa_rad = 1.5707963267948966;
};

// The cut's diameter for the recommendation: [cutting] diameter_mm, else the part's, else
// kDefaultDiameter_m.
double recommend_diameter_m(const LobesInput& in);
LobesInput load_lobes_input(const std::string& path);  // throws InputError
// The same from text (file_label names it in error messages); throws InputError.
LobesInput parse_lobes_input(std::string_view text, const std::string& file_label);
// The machine file's keys, with their ranges, defaults and meaning (the reader run without a file).
io::ParamLog describe_machine_file();
// The modes seen at the tool with the cutting position at x_m: the part's plus the tool's, plus
// the measured FRF (LobesMeasured: as read, or its fitted modes when sampled too coarsely); the
// modal one has the FRF's fitted modes instead.
dynamics::ChatterSystem lobes_system_at(const LobesInput& in, double x_m);
// The part's modes at x_m in its set-up; its first mode's frequency and static stiffness there.
std::vector<dynamics::Mode> part_modes_at(const LobesPart& part, double x_m);
double part_first_mode_Hz(const LobesPart& part, double x_m);
double part_static_stiffness(const LobesPart& part, double x_m);
dynamics::ChatterSystem lobes_modal_system_at(const LobesInput& in, double x_m);
// A machine file's structure at the tool as modes, for what needs modes beside the lobes (rig B's
// time-domain simulation, `optimize`'s chatter margin): its [[mode]]s and the modes fitted to its
// [[frf]]s (the fit the semi-discretization uses; the measured FRF itself only the frequency
// domain can read). A [part] is not part of it: the scenario describes its own part.
std::vector<dynamics::Mode> structure_modes(const LobesInput& in);
// The machine file named by the string `key` of table `t` (relative to t's file), read whole
// (every error of it as `lathectl lobes` gives it, after t's file and key) and refused at `key`
// when it describes a [part]; its structure_modes, at most max_modes of them. Describing: none.
std::vector<dynamics::Mode> read_structure_file(io::TableReader& t, std::string_view key,
                                                std::size_t max_modes);
// Fills in.measured from in.frfs (sum, fit, smoothing); throws std::invalid_argument when the
// FRF has no peak to fit.
void measure_frfs(LobesInput& in);
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

}  // namespace lathectl::systems::b_chatter
