#pragma once
// The chatter margin of each piece, from system B's lobes code and system E's cutting
// law, when the scenario has a [chatter] section (the tool's modes, the part between centres).
//
// Model (regenerative chatter with one delay, Tlusty & Polacek; Altintas, "Manufacturing
// Automation", 2nd ed., ch. 3.2–3.3; the code: dynamics/lobes.hpp). The structure seen at the
// tool along the chip-thickness direction — the feed direction, so the chip is the feed per
// revolution s — has the oriented FRF Φ(jω) of the tool's modes and the part's bending modes
// (B's beam between centres, at the tool's position, of the stock's diameter there). A small
// vibration y changes the chip by y(t − τ) − y(t) and the force by
//   dF = k_c·(y(t − τ) − y(t)),  k_c = ∂Pz/∂s  [N/m]
// (B's lobes write k_c = K_f·b with a chip-thickness coefficient K_f and the width b). The loop
// is stable at spindle speed n while k_c < k_lim(n), the lower envelope of the lobes
//   k_lim(n) = −1/(2·Re Φ(jω_c))  (ω_c the chatter frequency of the lobe at n),
// which is the lobes' limit depth at K_f = 1 N/m²: frequency_domain_lobes and envelope_depth on
// the modes with kf_N_per_m2 = 1 give it directly in N/m. SDOF closed form (one mode k, ζ along
// the chip): min over n of k_lim = 2kζ(1+ζ) (min Re G = −1/(4kζ(1+ζ)) at ω = ω_n·√(1+2ζ)).
//
// The cutting stiffness from E's law (cutting::CuttingModel, handbook Pz = 10·Cp·t^x·s^y·V^n·Kp
// or Kienzle F_c = k_c1.1·b·h^(1−m)): both are power laws in s and t, so
//   k_c = ∂Pz/∂s = y·Pz(t, s)/s ∝ t^x·s^(y−1)
// (y = 1 − m for Kienzle). With y < 1 (0.75 for steel) the stiffness per unit depth FALLS as the
// feed rises: a thicker chip is cut more easily per µm of thickness change. So the limit depth
//   t_lim = t·(k_lim/k_c)^(1/x)   (the depth at which k_c reaches k_lim; t·k_lim/k_c for x = 1)
// RISES with the feed as s^((1−y)/x), and the chatter margin t_lim/t = (k_lim/k_c)^(1/x) is a
// LOWER bound on the feed (or asks for another speed), never an upper one. The exponents y and x
// are taken from the law itself (logarithmic differences, exact for a power law), so Kienzle's
// b = t/sin κ and h = s·sin κ need no special case.
//
// Pz stands for the resultant: the modes' angles θ (cos²θ in Φ) carry the direction, as in B's
// machine files. Not modelled: process damping (raises the limit at low speed), the nose radius'
// overlap, and the radial regeneration of system B's rig (depth modulated by the part's radial
// bending through the overlap factor μ, whose gain ∂Py/∂t grows with the feed): with the part's
// bending modes at θ ≠ 90° this model counts them along the chip as B's machine files do.
#include <cstddef>
#include <cstdint>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "optimize/optimize.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::optimize {

// ∂Pz/∂s of E's law at a cutting state [N/m], and the law's exponents of s and t there.
struct ChipStiffness {
  double k_N_per_m = 0.0;
  double feed_exponent = 1.0;   // y (Kienzle: 1 − m)
  double depth_exponent = 1.0;  // x (Kienzle: 1)
};
ChipStiffness chip_stiffness(const cutting::CuttingModel& cut, const cutting::CutState& c) noexcept;

// Chatter margin t_lim/t = (k_lim/k_c)^(1/x); +inf when k_lim is infinite or not cutting.
double chatter_margin(double k_lim_N_per_m, const ChipStiffness& g) noexcept;

// k_lim(n) at a position, from the lobes of the modes seen there; lobes are computed per
// position (1 mm), diameter (0.1 mm) and speed band (1 %) and kept.
class ChatterLimit {
 public:
  // Reads [chatter] machine_file (system B's reader: every error of the machine file, after the
  // scenario's key; a [part] in it refused): its modes join the tool's. Throws io::InputError.
  explicit ChatterLimit(systems::e_adaptive::Chatter ch);
  [[nodiscard]] bool enabled() const { return ch_.enabled(); }
  // The modes seen at the tool at stock z with the part's diameter there (kf_N_per_m2 = 1).
  [[nodiscard]] dynamics::ChatterSystem system_at(double z_stock_mm, double diameter_mm) const;
  // −1/(2·Re Φ) on the lobes' lower envelope at `rpm` [N/m]; +inf where no lobe reaches.
  double critical_stiffness(double z_stock_mm, double diameter_mm, double rpm);
  [[nodiscard]] std::size_t lobes_computed() const { return cache_.size(); }

 private:
  systems::e_adaptive::Chatter ch_;
  std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, dynamics::FrequencyDomainResult>
      cache_;
  std::tuple<std::int64_t, std::int64_t, std::int64_t> last_key_{};  // the last query's
  double last_rpm_ = -1.0, last_k_ = 0.0;
};

// Per sample of a prediction in cut: k_lim there (s.kcrit) and the margin at the sample's depth,
// chip and speed (s.margin); NaN out of cut. z_origin: the machine z of the stock's z = 0.
void chatter_margins(Samples& s, ChatterLimit& lim, const cutting::CuttingModel& cut,
                     double z_origin_mm);

// The verdict on the final feeds, from the prediction `s` of `plan`: a piece whose least margin
// is below 1 ends its limited_by with " + chatter: ..." (the plan's "unstable at every feed
// within the limits", or "margin < 1" where its feed is below what the limits allow, e.g. one F
// for a whole line); the plan's flag is dropped where the prediction finds the piece stable (the
// plan judges on the original run's samples, whose longer time in cut wears the tool more).
void flag_chatter(Plan& plan, const Samples& s);

}  // namespace lathectl::optimize
