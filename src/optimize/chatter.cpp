// The chatter margin (chatter.hpp): E's cutting law's stiffness against system B's lobes.
#include "optimize/chatter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "lathectl/io/errors.hpp"
#include "optimize/optimize.hpp"
#include "systems/b_chatter/lobes_input.hpp"

namespace lathectl::optimize {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kBand = 0.01;  // speed band of one set of lobes (relative)
}  // namespace

ChipStiffness chip_stiffness(const cutting::CuttingModel& cut, const cutting::CutState& c) noexcept {
  ChipStiffness g;
  if (!(c.depth_mm > 0.0 && c.feed_mm_per_rev > 0.0)) return g;
  // The exponents as logarithmic differences over ±1 %: exact for a power law in s and t.
  constexpr double d = 0.01;
  const double l = std::log((1.0 + d) / (1.0 - d));
  auto pz = [&](double t, double s) {
    cutting::CutState x = c;
    x.depth_mm = t;
    x.feed_mm_per_rev = s;
    return cut.forces(x).Pz;
  };
  const double t = c.depth_mm, s = c.feed_mm_per_rev, p = pz(t, s);
  if (!(p > 0.0)) return g;
  g.feed_exponent = std::log(pz(t, s * (1.0 + d)) / pz(t, s * (1.0 - d))) / l;
  g.depth_exponent = std::log(pz(t * (1.0 + d), s) / pz(t * (1.0 - d), s)) / l;
  g.k_N_per_m = g.feed_exponent * p / s * 1e3;  // N/mm → N/m
  return g;
}

double chatter_margin(double k_lim, const ChipStiffness& g) noexcept {
  if (!(g.k_N_per_m > 0.0) || !std::isfinite(k_lim)) return kInf;
  return std::pow(k_lim / g.k_N_per_m, 1.0 / g.depth_exponent);
}

ChatterLimit::ChatterLimit(systems::e_adaptive::Chatter ch) : ch_(std::move(ch)) {
  if (ch_.machine_file.empty()) return;
  systems::b_chatter::LobesInput in;
  try {
    in = systems::b_chatter::load_lobes_input(ch_.machine_file);
  } catch (const io::InputError& e) {
    throw io::InputError(ch_.machine_file_at_key + ": the machine file: " + e.what());
  }
  if (in.part)
    throw io::InputError(ch_.machine_file_at_key + ": the machine file " + ch_.machine_file +
                         " describes a [part]; here [chatter.part] is the part: the machine file "
                         "gives the tool's side only ([[mode]], [[frf]])");
  const auto modes = systems::b_chatter::structure_modes(in);
  ch_.tool_modes.insert(ch_.tool_modes.end(), modes.begin(), modes.end());
}

dynamics::ChatterSystem ChatterLimit::system_at(double z_stock_mm, double diameter_mm) const {
  systems::b_chatter::LobesInput in;
  in.system.kf_N_per_m2 = 1.0;
  in.tool_modes = ch_.tool_modes;
  const double x_m = (z_stock_mm - ch_.tailstock_at_mm) * 1e-3;
  // Part modes while the tool is between the centres on material (at a centre the part rests on it).
  if (ch_.part && diameter_mm > 0.0 && x_m > 0.0 && x_m < ch_.beam.length_m) {
    systems::b_chatter::LobesPart part;
    part.beam = ch_.beam;
    part.beam.diameter_m = diameter_mm * 1e-3;
    part.modes = ch_.part_modes;
    part.position_m = x_m;
    in.part = part;
  }
  return systems::b_chatter::lobes_system_at(in, x_m);
}

double ChatterLimit::critical_stiffness(double z_stock_mm, double diameter_mm, double rpm) {
  if (!(rpm > 0.0)) return kInf;
  const bool part = ch_.part && z_stock_mm > ch_.tailstock_at_mm && z_stock_mm < ch_.headstock_at_mm;
  const auto band = static_cast<std::int64_t>(std::floor(std::log(rpm) / std::log1p(kBand)));
  const std::tuple<std::int64_t, std::int64_t, std::int64_t> key{
      band, part ? std::llround(z_stock_mm) : 0, part ? std::llround(diameter_mm * 10.0) : 0};
  if (rpm == last_rpm_ && key == last_key_) return last_k_;  // the same lobes, the same speed
  auto it = cache_.find(key);
  if (it == cache_.end()) {
    // The band's lobes with a margin on both sides, at the key's position and diameter.
    const double lo = std::pow(1.0 + kBand, static_cast<double>(band));
    systems::b_chatter::LobesInput in;
    in.system = system_at(part ? static_cast<double>(std::get<1>(key)) : z_stock_mm,
                          part ? 0.1 * static_cast<double>(std::get<2>(key)) : 0.0);
    in.modal = in.system;  // modes only: lobes_needed reads the modal system
    dynamics::FrequencyDomainResult fd;
    if (!in.system.modes.empty()) {
      in.min_rpm = lo / 1.05;
      in.max_rpm = lo * (1.0 + kBand) * 1.05;
      fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm,
                                            systems::b_chatter::lobes_needed(in));
    }
    it = cache_.emplace(key, std::move(fd)).first;
  }
  last_rpm_ = rpm;
  last_key_ = key;
  last_k_ = it->second.lobes.empty() ? kInf : dynamics::envelope_depth(it->second, rpm);
  return last_k_;
}

void chatter_margins(Samples& s, ChatterLimit& lim, const cutting::CuttingModel& cut,
                     double z_origin_mm) {
  const std::size_t n = s.depth.size();
  s.kcrit.assign(n, kNaN);
  s.margin.assign(n, kNaN);
  ChipStiffness law;  // the law's exponents: constants of a power law, found at the first sample
  bool have_law = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(s.depth[i] > 0.0 && s.feed_rev[i] > 0.0)) continue;
    // The part's diameter at the tool before this pass: the radius it leaves plus the depth.
    const double k = lim.critical_stiffness(z_origin_mm - s.z[i], 2.0 * (s.x[i] + s.depth[i]),
                                            s.rpm[i]);
    const cutting::CutState c{s.depth[i], s.feed_rev[i], s.speed[i], s.strength[i], s.wear[i]};
    if (!have_law) {
      law = chip_stiffness(cut, c);
      have_law = law.k_N_per_m > 0.0;
    }
    ChipStiffness g = law;  // k_c = y·Pz/s (chip_stiffness without its four extra force calls)
    g.k_N_per_m = law.feed_exponent * cut.forces(c).Pz / s.feed_rev[i] * 1e3;
    s.kcrit[i] = k;
    s.margin[i] = chatter_margin(k, g);
  }
}

void flag_chatter(Plan& plan, const Samples& s) {
  std::vector<std::vector<double>> least(plan.size());
  for (std::size_t mi = 0; mi < plan.size(); ++mi) least[mi].assign(plan[mi].size(), kInf);
  for (std::size_t i = 0; i < s.margin.size(); ++i)
    if (s.margin[i] >= 0.0) {  // NaN: not in cut
      double& m = least[static_cast<std::size_t>(s.move[i])][static_cast<std::size_t>(s.piece[i])];
      m = std::min(m, s.margin[i]);
    }
  const std::string unstable = " + chatter: unstable at every feed within the limits";
  for (std::size_t mi = 0; mi < plan.size(); ++mi)
    for (std::size_t k = 0; k < plan[mi].size(); ++k) {
      std::string& why = plan[mi][k].limited_by;
      const auto at = why.find(" + chatter");
      const bool planned = at != std::string::npos;
      if (planned) why.erase(at);
      if (least[mi][k] < 1.0) why += planned ? unstable : " + chatter: margin < 1";
    }
}

}  // namespace lathectl::optimize
