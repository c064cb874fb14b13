#pragma once
// Cutting-force, power, tool-life and roughness model for turning (all systems).
//
// Handbook form (Kosilova & Meshcheryakov, "Spravochnik tekhnologa-mashinostroitelya", t.2):
//   P_i = 10 · Cp_i · t^x_i · s^y_i · V^n_i · Kp          [N]
//   t depth [mm], s feed [mm/rev], V cutting speed [m/min], i ∈ {z, y, x}
//   Kp = Kmp · (hardness and wear factors of the disturbances)
//   Kmp = (strength / strength_base)^kmp_exponent (σв for steel, HB for cast iron)
// Kienzle form (König & Essel; Degner, Lutze, Smejkal "Spanende Formung"):
//   F_i = k_i1.1 · b · h^(1 − m_i),  b = t / sin κ,  h = s · sin κ    [N; mm]
//   Fc ↔ Pz, Fp (passive) ↔ Py, Ff (feed) ↔ Px
// Power: Nc = Pz · V.  Tool life (extended Taylor, handbook): V = Cv·Kmv / (T^m · t^xv · s^yv),
// so T = (Cv·Kmv / (V · t^xv · s^yv))^(1/m) [min]; the coefficients depend on the feed range.
// Kmv = (strength_base / (strength·h))^kmv_exponent, h the local hardness (strength) factor:
// the handbook's Kmv = Kг·(750/σв)^nv for steel (nv = 1.0 for carbide tools) or (190/HB)^nv for
// grey cast iron (nv = 1.25), Kosilova & Meshcheryakov vol. 2, ch. "Turning", tables 1–2 of
// the speed corrections. The material file folds the material's own Kmv into Cv (steel_40Kh);
// here it applies to the local factor h (the material's strength/strength_base is 1 there).
// Wear: T is the time to the handbook's flank-wear criterion, so ∫dt/T (Palmgren–Miner) is the
// share of that wear used; the handbook gives no further wear term in V.
// Roughness: Rz = s² / (8 r), Ra ≈ s² / (32 r) (r nose radius).
//
// Units here are the handbook's shop units (mm, mm/rev, m/min, N); callers convert from SI.
// All evaluation calls are noexcept and allocation-free.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "lathectl/cutting/feed_range.hpp"

namespace lathectl::cutting {

struct PowerLaw {  // handbook force law 10·Cp·t^x·s^y·V^n
  bool operator==(const PowerLaw&) const = default;
  double Cp = 0.0;
  double x = 1.0;
  double y = 1.0;
  double n = 0.0;
};

struct KienzleLaw {  // k1.1 · b · h^(1 − m)
  bool operator==(const KienzleLaw&) const = default;
  double k11_N_per_mm2 = 0.0;
  double m = 0.0;
};

struct ToolLifeRange {  // extended Taylor law valid for feeds up to feed_max_mm_per_rev
  bool operator==(const ToolLifeRange&) const = default;
  double feed_max_mm_per_rev = 1e9;
  double Cv = 0.0;
  double xv = 0.0;
  double yv = 0.0;
  double m = 0.2;
};

struct Material {
  bool operator==(const Material&) const = default;
  std::string name;
  std::string description;
  std::string strength_basis;                // "sigma_b_MPa" or "HB"
  double strength = 0.0;                     // of this material, in strength_basis units
  double strength_base = 0.0;                // the handbook coefficients' reference strength
  double kmp_exponent = 0.0;                 // Kmp = (strength/base)^exponent
  PowerLaw Pz, Py, Px;                       // handbook form
  KienzleLaw Fc, Fp, Ff;                     // Kienzle form
  std::array<ToolLifeRange, 3> tool_life{};  // ascending feed ranges
  int tool_life_ranges = 0;
  double kmv_exponent = 0.0;  // nv of Kmv = (base/strength)^nv (tool life; 0 = no hardness term)
};

enum class ForceForm { Handbook, Kienzle };

struct Forces {
  double Pz = 0.0;  // tangential [N]
  double Py = 0.0;  // radial (passive) [N]
  double Px = 0.0;  // axial (feed) [N]
};

struct CutState {
  double depth_mm = 0.0;         // t
  double feed_mm_per_rev = 0.0;  // s
  double speed_m_per_min = 0.0;  // V
  double strength_factor = 1.0;  // local hardness / strength relative to the material's
  double wear_factor = 1.0;      // force growth from flank wear (≥ 1)
};

class CuttingModel {
 public:
  struct Params {
    bool operator==(const Params&) const = default;
    Material material;
    ForceForm form = ForceForm::Handbook;
    double approach_angle_deg = 90.0;  // κ in (0, 95]°, Kienzle form only
    double nose_radius_mm = 0.8;
  };
  void configure(const Params& p);  // throws std::invalid_argument on bad data

  // Forces for one cutting state; zero when depth or feed is not positive (tool out of cut).
  [[nodiscard]] Forces forces(const CutState& c) const noexcept;
  // Pz and Py alone, Px left 0: the same two numbers as forces(), one force law fewer (three
  // pow a step on rig E, whose plant reports no Px).
  [[nodiscard]] Forces forces_pz_py(const CutState& c) const noexcept;
  // Only the radial force (cheaper: one power law, V^n cached). Not thread-safe on a shared
  // instance: each rig owns its model.
  [[nodiscard]] double radial_force(const CutState& c) const noexcept;
  // Cutting power Nc = Pz·V [W].
  [[nodiscard]] double power_W(const Forces& f, double speed_m_per_min) const noexcept;
  // Tool life T [min] at V, s, t and local strength factor h (extended Taylor with Kmv);
  // +inf when not cutting.
  [[nodiscard]] double tool_life_min(double speed_m_per_min, double feed_mm_per_rev,
                                     double depth_mm,
                                     double strength_factor = 1.0) const noexcept;
  // Speed [m/min] giving tool life T_min at s, t, h.
  [[nodiscard]] double speed_for_life(double life_min, double feed_mm_per_rev, double depth_mm,
                                      double strength_factor = 1.0) const noexcept;
  // Kmv of the local strength factor h: (1/h)^kmv_exponent (1 at h = 1).
  [[nodiscard]] double kmv(double strength_factor) const noexcept;
  [[nodiscard]] double roughness_Rz_um(double feed_mm_per_rev) const noexcept;
  [[nodiscard]] double roughness_Ra_um(double feed_mm_per_rev) const noexcept;
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  [[nodiscard]] double kmp() const noexcept { return kmp_; }

 private:
  [[nodiscard]] const ToolLifeRange& life_range(double feed_mm_per_rev) const noexcept;
  [[nodiscard]] Forces forces_of(const CutState& c, bool with_px) const noexcept;
  [[nodiscard]] double radial_force_kienzle(const CutState& c, double k) const noexcept;
  [[nodiscard]] static double power_law(const PowerLaw& law, const CutState& c, double kp) noexcept {
    return 10.0 * law.Cp * std::pow(c.depth_mm, law.x) * std::pow(c.feed_mm_per_rev, law.y) *
           std::pow(c.speed_m_per_min, law.n) * kp;
  }
  [[nodiscard]] static double kienzle(const KienzleLaw& law, double b_mm, double h_mm) noexcept {
    return law.k11_N_per_mm2 * b_mm * std::pow(h_mm, 1.0 - law.m);
  }
  [[nodiscard]] static double hardness_kp(double kmp_exponent, double strength_factor) noexcept {
    return strength_factor == 1.0 ? 1.0 : std::pow(strength_factor, kmp_exponent);
  }
  Params p_{};
  double kmp_ = 1.0;
  double sin_kappa_ = 1.0;
  mutable double cached_speed_ = -1.0;  // V^n of Py for the last V (radial_force hot path)
  mutable double cached_speed_term_ = 1.0;
  // base^exponent for the last pair asked (the same value std::pow gives): a rig steps
  // radial_force and tool_life_min every step, the depth changes far less often than that, and
  // rig E asks the tool life twice a step at one feed (with and without the hardness). On rig
  // A the tool-life law's three pow a step were all the time it lost since 42a2cf0. The bases
  // are > 0 where it is used (±0 compare equal but may give different powers).
  struct LastPow {
    double base = std::numeric_limits<double>::quiet_NaN();
    double exponent = std::numeric_limits<double>::quiet_NaN();
    double value = 0.0;
    double operator()(double b, double e) noexcept {
      if (!(b == base && e == exponent)) {  // NaN at first: never equal
        base = b;
        exponent = e;
        value = std::pow(b, e);
      }
      return value;
    }
  };
  mutable LastPow depth_force_;  // t^x of Py (radial_force)
  mutable LastPow depth_life_;   // t^xv (tool_life_min)
  mutable LastPow feed_life_;    // s^yv (tool_life_min)
};

// The per-step laws in the header (issue 45 item 6): a rig calls them every step, and out of
// line each call stored and reloaded the rig's state around it.
inline Forces CuttingModel::forces(const CutState& c) const noexcept { return forces_of(c, true); }

inline Forces CuttingModel::forces_pz_py(const CutState& c) const noexcept { return forces_of(c, false); }

inline Forces CuttingModel::forces_of(const CutState& c, bool with_px) const noexcept {
  if (!(c.depth_mm > 0.0) || !(c.feed_mm_per_rev > 0.0)) return {};
  const double k = kmp_ * hardness_kp(p_.material.kmp_exponent, c.strength_factor) * c.wear_factor;
  if (p_.form == ForceForm::Handbook) {
    const double v = std::max(c.speed_m_per_min, 1.0);  // the power law has no meaning at V→0
    const CutState cv{c.depth_mm, c.feed_mm_per_rev, v, 1.0, 1.0};
    return {power_law(p_.material.Pz, cv, k), power_law(p_.material.Py, cv, k),
            with_px ? power_law(p_.material.Px, cv, k) : 0.0};
  }
  // The Kienzle constants are the material's own (data/materials.toml gives them per grade):
  // Kmp, the handbook's strength correction to its reference grade, does not apply; the local
  // hardness and wear factors do.
  const double kk = k / kmp_;
  const double b = c.depth_mm / sin_kappa_;
  const double h = c.feed_mm_per_rev * sin_kappa_;
  return {kienzle(p_.material.Fc, b, h) * kk, kienzle(p_.material.Fp, b, h) * kk,
          with_px ? kienzle(p_.material.Ff, b, h) * kk : 0.0};
}

inline double CuttingModel::radial_force(const CutState& c) const noexcept {
  if (!(c.depth_mm > 0.0) || !(c.feed_mm_per_rev > 0.0)) return 0.0;
  const double k = kmp_ * hardness_kp(p_.material.kmp_exponent, c.strength_factor) * c.wear_factor;
  if (p_.form != ForceForm::Handbook) return radial_force_kienzle(c, k);
  const double v = std::max(c.speed_m_per_min, 1.0);
  if (v != cached_speed_) {  // the speed changes far less often than depth and feed
    cached_speed_ = v;
    cached_speed_term_ = std::pow(v, p_.material.Py.n);
  }
  const auto& law = p_.material.Py;
  return 10.0 * law.Cp * depth_force_(c.depth_mm, law.x) * std::pow(c.feed_mm_per_rev, law.y) *
         cached_speed_term_ * k;
}

inline const ToolLifeRange& CuttingModel::life_range(double feed_mm_per_rev) const noexcept {
  return feed_range(p_.material.tool_life, p_.material.tool_life_ranges, feed_mm_per_rev);
}

inline double CuttingModel::kmv(double strength_factor) const noexcept {
  const double nv = p_.material.kmv_exponent;
  return strength_factor == 1.0 || nv == 0.0 || !(strength_factor > 0.0)
             ? 1.0
             : std::pow(strength_factor, -nv);
}

inline double CuttingModel::tool_life_min(double speed_m_per_min, double feed_mm_per_rev,
                                          double depth_mm, double strength_factor) const noexcept {
  if (p_.material.tool_life_ranges == 0 || !(speed_m_per_min > 0.0) || !(feed_mm_per_rev > 0.0) ||
      !(depth_mm > 0.0))
    return std::numeric_limits<double>::infinity();
  const auto& r = life_range(feed_mm_per_rev);
  const double ratio = r.Cv * kmv(strength_factor) /
                       (speed_m_per_min * depth_life_(depth_mm, r.xv) * feed_life_(feed_mm_per_rev, r.yv));
  return std::pow(ratio, 1.0 / r.m);
}

}  // namespace lathectl::cutting
