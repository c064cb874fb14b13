// libFuzzer target for `lathectl lobes`: any input must either throw InputError located in the
// file, or parse into a machine the command can compute within its bounds. Beyond the parser it
// runs, cheaply, what the command does with a parsed file: the lobes needed, the cost estimate
// (within kMaxBytes and kMaxSeconds), the beam's modes at every position, the frequency-domain
// lobes on a coarse grid at every position, and, for small systems, a 3 × 3 SD chart at a few
// steps per revolution. Anything else escaping (std::invalid_argument from dynamics/ is what
// `lathectl lobes` printed as "internal error"), or a SIGSEGV, is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "lathectl/io/errors.hpp"
#include "systems/b_chatter/lobes.hpp"

namespace {
using namespace lathectl;

void check(bool ok) {
  if (!ok) std::abort();
}

void exercise(const systems::b_chatter::LobesInput& in) {
  check(!in.modal.modes.empty() && in.system.kf_N_per_m2 > 0.0 && in.max_rpm > in.min_rpm);
  for (const auto& m : in.modal.modes)
    check(m.stiffness_N_per_m > 0.0 && m.natural_frequency_Hz > 0.0 &&
          std::isfinite(m.stiffness_N_per_m));
  check(systems::b_chatter::lobes_needed(in) <= systems::b_chatter::kMaxLobes);
  const auto cost = systems::b_chatter::lobes_cost(in, 2);
  check(std::isfinite(cost.seconds) && cost.seconds <= systems::b_chatter::kMaxSeconds);
  check(std::isfinite(cost.bytes) && cost.bytes <= systems::b_chatter::kMaxBytes);

  std::vector<double> xs;
  if (in.part) {
    xs.push_back(in.part->position_m);
    xs.insert(xs.end(), in.part->positions_m.begin(), in.part->positions_m.end());
  }
  // As run_lobes: every position's modes (the first mode's frequency and the static stiffness
  // are read there) and its lobes, on 400 frequencies instead of 40 000.
  for (double x : xs) {
    check(!dynamics::beam_modes_at(in.part->beam, x, in.part->modes).empty());
    check(std::isfinite(dynamics::beam_static_stiffness(in.part->beam, x)));
    const auto sys = systems::b_chatter::lobes_system_at(in, x);
    const auto fd =
        dynamics::frequency_domain_lobes(sys, in.min_rpm, in.max_rpm, in.max_lobes, 400);
    (void)dynamics::envelope_depth(fd, 0.5 * (in.min_rpm + in.max_rpm));
  }
  const auto fd =
      dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes, 400);
  if (in.modal.modes.size() > 4 || !std::isfinite(fd.critical_depth_m)) return;
  dynamics::SdChartOptions o;
  o.steps_per_period = 2;
  o.min_steps = 4;
  o.max_steps = 40;
  o.threads = 1;
  const double top =
      in.chart_max_depth_m > 0.0 ? in.chart_max_depth_m : 4.0 * fd.critical_depth_m;
  (void)dynamics::sd_stability_chart(in.modal, in.min_rpm, in.max_rpm, 3, top, 3, o);
  (void)dynamics::sd_limit_depth(in.modal, in.max_rpm, 3.0 * fd.critical_depth_m, 10, 1e-2, 5);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  systems::b_chatter::LobesInput in;
  try {
    in = systems::b_chatter::parse_lobes_input(text, "fuzz.toml");
  } catch (const io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.toml") == std::string_view::npos) std::abort();
    return 0;
  }
  exercise(in);  // a parsed machine: nothing may throw from here on
  return 0;
}
