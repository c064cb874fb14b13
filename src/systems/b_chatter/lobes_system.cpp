#include "systems/b_chatter/lobes_input.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

// The modes a lobe chart or the optimiser's chatter margin sees (lobes.hpp): no file, no TOML, in
// the settings library, so that lathectl optimize links no more of system B than this.

namespace lathectl::systems::b_chatter {

namespace {

// The chatter frequency f_n·√(1+2ζ) of the highest mode that can chatter (see lobes_needed).
double reference_Hz(const dynamics::ChatterSystem& sys) {
  double lowest = std::numeric_limits<double>::infinity();
  auto limit = [&](const dynamics::Mode& m) {
    const double c2 = std::max(std::cos(m.angle_rad) * std::cos(m.angle_rad), 1e-12);
    return 2.0 * m.stiffness_N_per_m * m.damping_ratio * (1.0 + m.damping_ratio) / c2;
  };
  for (const auto& m : sys.modes) lowest = std::min(lowest, limit(m));
  double f = 0.0;
  for (const auto& m : sys.modes)
    if (limit(m) <= 3.0 * lowest)
      f = std::max(f, m.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * m.damping_ratio));
  return f;
}

}  // namespace

double lobes_reference_Hz(const LobesInput& in) {
  double f = reference_Hz(in.modal);
  if (in.part)
    for (double x : in.part->positions_m)
      f = std::max(f, reference_Hz(lobes_modal_system_at(in, x)));
  return f;
}

double lobes_needed_count(const LobesInput& in) {
  return std::ceil(60.0 * lobes_reference_Hz(in) / in.min_rpm) + 2.0;
}

int lobes_needed(const LobesInput& in) {
  // Saturated, never an overflow (the cast of 10¹⁵ lobes was undefined); the reader refuses a
  // file over kMaxLobes, and `optimize` (src/optimize/chatter.cpp) asks at real spindle speeds.
  const double n = lobes_needed_count(in);
  return static_cast<int>(std::min(n, static_cast<double>(std::numeric_limits<int>::max() / 2)));
}

std::vector<dynamics::Mode> part_modes_at(const LobesPart& part, double x_m) {
  if (part.model) return dynamics::beam_model_modes_at(*part.model, x_m);
  return dynamics::beam_modes_at(part.beam, x_m, part.modes);
}

double part_first_mode_Hz(const LobesPart& part, double x_m) {
  if (part.model) return part.model->omega_rad_s.front() / (2.0 * std::numbers::pi);
  return dynamics::beam_mode_at(part.beam, x_m, 1).mode.natural_frequency_Hz;
}

double part_static_stiffness(const LobesPart& part, double x_m) {
  if (part.model) return dynamics::beam_model_static_stiffness(*part.model, x_m);
  return dynamics::beam_static_stiffness(part.beam, x_m);
}

dynamics::ChatterSystem lobes_modal_system_at(const LobesInput& in, double x_m) {
  dynamics::ChatterSystem sys;
  sys.kf_N_per_m2 = in.system.kf_N_per_m2;
  if (in.part) sys.modes = part_modes_at(*in.part, x_m);
  sys.modes.insert(sys.modes.end(), in.tool_modes.begin(), in.tool_modes.end());
  if (in.measured)
    sys.modes.insert(sys.modes.end(), in.measured->fit.modes.begin(), in.measured->fit.modes.end());
  return sys;
}

dynamics::ChatterSystem lobes_system_at(const LobesInput& in, double x_m) {
  dynamics::ChatterSystem sys;
  sys.kf_N_per_m2 = in.system.kf_N_per_m2;
  if (in.part) sys.modes = part_modes_at(*in.part, x_m);
  sys.modes.insert(sys.modes.end(), in.tool_modes.begin(), in.tool_modes.end());
  if (in.measured) sys.frfs.push_back(in.measured->smoothed);
  sys.process_damping_C = in.process_damping_C;
  return sys;
}

double recommend_diameter_m(const LobesInput& in) {
  if (in.recommend.diameter_m > 0.0) return in.recommend.diameter_m;
  if (in.part) return in.part->beam.diameter_m;
  return kDefaultDiameter_m;
}

std::vector<dynamics::Mode> structure_modes(const LobesInput& in) {
  std::vector<dynamics::Mode> modes = in.tool_modes;
  if (in.measured)
    modes.insert(modes.end(), in.measured->fit.modes.begin(), in.measured->fit.modes.end());
  return modes;
}

void measure_frfs(LobesInput& in) {
  if (in.frfs.empty()) {
    in.measured.reset();
    return;
  }
  LobesMeasured m;
  std::vector<dynamics::Frf> weighted;
  for (const auto& f : in.frfs) {
    dynamics::Frf w = f.frf;
    for (auto& h : w.receptance_m_per_N) h *= f.weight;
    weighted.push_back(std::move(w));
  }
  m.oriented = dynamics::sum_frfs(weighted);
  m.fit = dynamics::fit_modes(m.oriented);
  m.samples_per_bandwidth = dynamics::samples_per_bandwidth(m.oriented, m.fit);
  m.read_directly = m.samples_per_bandwidth >= dynamics::kMinSamplesPerBandwidth;
  m.smoothing_half_window_Hz = dynamics::smoothing_half_window_Hz(m.fit) *
                               (m.read_directly ? 1.0 : dynamics::kCoarseWindowFactor);
  m.smoothed = dynamics::smooth_against_fit(m.oriented, m.fit, m.smoothing_half_window_Hz,
                                            dynamics::kSmoothingOrder);
  in.measured = std::move(m);
}

}  // namespace lathectl::systems::b_chatter
