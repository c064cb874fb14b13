// Cutting model against the handbook formulas worked by hand (docs/materials-reference.md;
// Kosilova & Meshcheryakov vol. 2, tables 17 and 22) and against the Kienzle form.

#include "support/library.hpp"
#include "lathectl/cutting/cutting_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "lathectl/io/materials.hpp"

namespace lathectl::cutting {
namespace {

using lathectl::test::library;

CuttingModel model(const std::string& material, ForceForm form = ForceForm::Handbook,
                   double kappa_deg = 90.0, double nose_radius_mm = 0.8) {
  const Material* m = library().find(material);
  EXPECT_NE(m, nullptr) << material;
  CuttingModel cm;
  cm.configure({*m, form, kappa_deg, nose_radius_mm});
  return cm;
}

constexpr CutState kRef{2.0, 0.3, 100.0, 1.0, 1.0};  // t = 2 mm, s = 0.3 mm/rev, V = 100 m/min

TEST(CuttingModel, MaterialFileHoldsTheHandbookCoefficients) {
  const Material* m = library().find("steel_45");
  ASSERT_NE(m, nullptr);
  // Handbook, steel 45: Pz Cp=300 x=1 y=0.75 n=-0.15; Py 243/0.9/0.6/-0.3; Px 339/1/0.5/-0.4.
  EXPECT_DOUBLE_EQ(m->Pz.Cp, 300.0);
  EXPECT_DOUBLE_EQ(m->Pz.y, 0.75);
  EXPECT_DOUBLE_EQ(m->Py.Cp, 243.0);
  EXPECT_DOUBLE_EQ(m->Py.x, 0.9);
  EXPECT_DOUBLE_EQ(m->Px.n, -0.4);
  EXPECT_EQ(m->tool_life_ranges, 3);
  EXPECT_EQ(library().find("no_such_material"), nullptr);
}

TEST(CuttingModel, HandbookForcesSteel45MatchHandComputation) {
  const auto cm = model("steel_45");
  EXPECT_DOUBLE_EQ(cm.kmp(), 1.0);  // σв = base = 750 MPa → Kmp = 1
  const Forces f = cm.forces(kRef);

  // Independent evaluation of P = 10·Cp·t^x·s^y·V^n.
  const double pz =
      10.0 * 300.0 * std::pow(2.0, 1.0) * std::pow(0.3, 0.75) * std::pow(100.0, -0.15);
  const double py = 10.0 * 243.0 * std::pow(2.0, 0.9) * std::pow(0.3, 0.6) * std::pow(100.0, -0.3);
  const double px = 10.0 * 339.0 * std::pow(2.0, 1.0) * std::pow(0.3, 0.5) * std::pow(100.0, -0.4);
  EXPECT_NEAR(f.Pz, pz, 1e-9 * pz);
  EXPECT_NEAR(f.Py, py, 1e-9 * py);
  EXPECT_NEAR(f.Px, px, 1e-9 * px);

  // Worked by hand: 0.3^0.75 = e^(0.75·ln 0.3) = e^(−0.90298) = 0.405360;
  //                 100^−0.15 = e^(−0.15·4.60517) = e^(−0.690776) = 0.501187;
  //                 Pz = 10·300·2·0.405360·0.501187 = 6000·0.203161 = 1218.97 N.
  EXPECT_NEAR(f.Pz, 1218.97, 0.01);
  // Py = 2430·2^0.9·0.3^0.6·100^−0.3 = 2430·1.866066·0.485593·0.251189 = 553.10 N.
  EXPECT_NEAR(f.Py, 553.10, 0.01);
  // Px = 3390·2·0.547723·0.158489 = 588.56 N.
  EXPECT_NEAR(f.Px, 588.56, 0.01);

  // radial_force() is the same Py law.
  EXPECT_DOUBLE_EQ(cm.radial_force(kRef), f.Py);
}

TEST(CuttingModel, PowerIsPzTimesSpeed) {
  const auto cm = model("steel_45");
  const Forces f = cm.forces(kRef);
  // Nc = Pz·V, V = 100 m/min = 100/60 m/s → 1218.97·1.6667 = 2031.6 W.
  EXPECT_NEAR(cm.power_W(f, 100.0), f.Pz * 100.0 / 60.0, 1e-9);
  EXPECT_NEAR(cm.power_W(f, 100.0), 2031.6, 0.1);
}

TEST(CuttingModel, MaterialFactorForSteel40Kh) {
  const auto c45 = model("steel_45");
  const auto c40 = model("steel_40Kh");
  // Kmp = (σв/750)^0.75 = (980/750)^0.75 = 1.30667^0.75 = e^(0.75·0.267496) = 1.22215.
  const double kmp = std::pow(980.0 / 750.0, 0.75);
  EXPECT_NEAR(c40.kmp(), kmp, 1e-12);
  EXPECT_NEAR(c40.kmp(), 1.22215, 1e-5);
  const Forces a = c45.forces(kRef);
  const Forces b = c40.forces(kRef);
  EXPECT_NEAR(b.Pz / a.Pz, kmp, 1e-12);
  EXPECT_NEAR(b.Py / a.Py, kmp, 1e-12);
  EXPECT_NEAR(b.Px / a.Px, kmp, 1e-12);
}

TEST(CuttingModel, ZeroForceOutOfCut) {
  for (const auto form : {ForceForm::Handbook, ForceForm::Kienzle}) {
    const auto cm = model("steel_45", form);
    for (const CutState c :
         {CutState{0.0, 0.3, 100.0, 1.0, 1.0}, CutState{2.0, 0.0, 100.0, 1.0, 1.0},
          CutState{-1.0, 0.3, 100.0, 1.0, 1.0}, CutState{2.0, -0.1, 100.0, 1.0, 1.0},
          CutState{std::nan(""), 0.3, 100.0, 1.0, 1.0}}) {
      const Forces f = cm.forces(c);
      EXPECT_EQ(f.Pz, 0.0);
      EXPECT_EQ(f.Py, 0.0);
      EXPECT_EQ(f.Px, 0.0);
      EXPECT_EQ(cm.radial_force(c), 0.0);
    }
  }
}

// forces_pz_py (the lathe plant's) gives forces()'s Pz and Py, the same doubles, and no Px.
TEST(CuttingModel, PzPyAloneAreTheForcesPzAndPy) {
  for (const auto form : {ForceForm::Handbook, ForceForm::Kienzle}) {
    const auto cm = model("steel_40Kh", form, 60.0);
    for (const CutState c : {kRef, CutState{0.37, 0.071, 212.3, 1.17, 1.09}}) {
      const auto all = cm.forces(c);
      const auto two = cm.forces_pz_py(c);
      EXPECT_EQ(two.Pz, all.Pz);
      EXPECT_EQ(two.Py, all.Py);
      EXPECT_GT(all.Px, 0.0);
      EXPECT_EQ(two.Px, 0.0);
    }
  }
}

TEST(CuttingModel, StrengthFactorScalesAsPowerOfKmpExponent) {
  for (const auto form : {ForceForm::Handbook, ForceForm::Kienzle}) {
    const auto cm = model("steel_45", form);
    const Forces base = cm.forces(kRef);
    for (const double x : {0.5, 1.3, 2.52}) {
      CutState c = kRef;
      c.strength_factor = x;
      const Forces f = cm.forces(c);
      // Kp ∝ (σ/σ_base)^kmp_exponent, exponent 0.75 for steel_45.
      const double k = std::pow(x, 0.75);
      EXPECT_NEAR(f.Pz / base.Pz, k, 1e-12);
      EXPECT_NEAR(f.Py / base.Py, k, 1e-12);
      EXPECT_NEAR(f.Px / base.Px, k, 1e-12);
      EXPECT_NEAR(cm.radial_force(c) / base.Py, k, 1e-12);
    }
  }
  // By hand: 2.52^0.75 = e^(0.75·ln 2.52) = e^(0.75·0.924259) = e^0.693194 = 2.0001 — the factor
  // examples/scenarios/a_roughing_fim.toml uses to double Py.
  CutState c = kRef;
  c.strength_factor = 2.52;
  EXPECT_NEAR(model("steel_45").forces(c).Py / model("steel_45").forces(kRef).Py, 2.0001, 1e-4);
}

TEST(CuttingModel, WearFactorIsLinear) {
  const auto cm = model("steel_45");
  const Forces base = cm.forces(kRef);
  for (const double w : {1.0, 1.075, 1.5}) {
    CutState c = kRef;
    c.wear_factor = w;
    const Forces f = cm.forces(c);
    EXPECT_NEAR(f.Pz, w * base.Pz, 1e-9);
    EXPECT_NEAR(f.Py, w * base.Py, 1e-9);
    EXPECT_NEAR(f.Px, w * base.Px, 1e-9);
  }
}

TEST(CuttingModel, HandbookSpeedBelowOneMetrePerMinuteIsClampedNotInfinite) {
  // V^n with n < 0 diverges at V → 0; the model evaluates at V = 1 m/min instead.
  const auto cm = model("steel_45");
  const Forces f0 = cm.forces({2.0, 0.3, 0.0, 1.0, 1.0});
  const Forces f1 = cm.forces({2.0, 0.3, 1.0, 1.0, 1.0});
  EXPECT_TRUE(std::isfinite(f0.Pz));
  EXPECT_DOUBLE_EQ(f0.Pz, f1.Pz);
  EXPECT_DOUBLE_EQ(f0.Py, f1.Py);
  // At V = 1 the speed factor is 1: Pz = 10·300·2·0.3^0.75 = 2432.16 N.
  EXPECT_NEAR(f1.Pz, 6000.0 * std::pow(0.3, 0.75), 1e-9);
}

TEST(CuttingModel, KienzleAtNinetyDegrees) {
  const auto cm = model("steel_45", ForceForm::Kienzle, 90.0);
  const Forces f = cm.forces(kRef);
  // κ = 90°: b = t = 2 mm, h = s = 0.3 mm. Fc = 1490·2·0.3^(1−0.26).
  EXPECT_NEAR(f.Pz, 1490.0 * 2.0 * std::pow(0.3, 0.74), 1e-9);
  EXPECT_NEAR(f.Py, 274.0 * 2.0 * std::pow(0.3, 0.51), 1e-9);
  EXPECT_NEAR(f.Px, 351.0 * 2.0 * std::pow(0.3, 0.30), 1e-9);
  // By hand: 0.3^0.74 = e^(0.74·−1.203973) = e^(−0.890940) = 0.410265 → Fc = 2980·0.410265 = 1222.6
  // N.
  EXPECT_NEAR(f.Pz, 1222.6, 0.05);
}

// The Kienzle constants in data/materials.toml are per grade (40Kh: k1.1 = 1940, 357 N/mm²), so
// the handbook's strength correction Kmp = (980/750)^0.75 = 1.222 must not multiply them again.
TEST(CuttingModel, KienzleUsesTheGradesOwnConstants) {
  const auto cm = model("steel_40Kh", ForceForm::Kienzle, 90.0);
  const Forces f = cm.forces(kRef);
  EXPECT_NEAR(f.Pz, 1940.0 * 2.0 * std::pow(0.3, 0.74), 1e-9);
  EXPECT_NEAR(f.Py, 357.0 * 2.0 * std::pow(0.3, 0.51), 1e-9);
  EXPECT_NEAR(cm.radial_force(kRef), f.Py, 1e-9);
  // The handbook form still carries Kmp (its coefficients are for σв = 750 MPa).
  EXPECT_GT(model("steel_40Kh", ForceForm::Handbook, 90.0).kmp(), 1.2);
}

TEST(CuttingModel, KienzleAtFortyFiveDegrees) {
  const auto cm = model("steel_45", ForceForm::Kienzle, 45.0);
  const Forces f = cm.forces(kRef);
  // κ = 45°: b = t/sin κ = 2/0.707107 = 2.828427 mm, h = s·sin κ = 0.212132 mm.
  const double b = 2.0 / std::sin(std::numbers::pi / 4.0);
  const double h = 0.3 * std::sin(std::numbers::pi / 4.0);
  EXPECT_NEAR(f.Pz, 1490.0 * b * std::pow(h, 0.74), 1e-9);
  EXPECT_NEAR(f.Py, 274.0 * b * std::pow(h, 0.51), 1e-9);
  EXPECT_NEAR(f.Px, 351.0 * b * std::pow(h, 0.30), 1e-9);
  // Fc = 1490·2.828427·0.212132^0.74 = 4214.36·0.317461 = 1337.9 N: the thinner, wider chip
  // costs more force (h^−mc grows as h shrinks).
  EXPECT_NEAR(f.Pz, 1337.9, 0.05);
  EXPECT_NEAR(cm.radial_force(kRef), f.Py, 1e-12);
}

// The common 95° turning tool (a DCLNR-type holder): b = t/sin 95° = 2/0.996195 = 2.007639 mm,
// h = s·sin 95° = 0.298858 mm, the chip of an 85° edge; past 95° the model refuses the tool.
TEST(CuttingModel, KienzleAtNinetyFiveDegreesAndNoFurther) {
  const auto cm = model("steel_45", ForceForm::Kienzle, 95.0);
  const Forces f = cm.forces(kRef);
  const double s95 = std::sin(95.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(s95, 0.996195, 1e-6);
  EXPECT_NEAR(f.Pz, 1490.0 * (2.0 / s95) * std::pow(0.3 * s95, 0.74), 1e-9);
  EXPECT_NEAR(f.Py, 274.0 * (2.0 / s95) * std::pow(0.3 * s95, 0.51), 1e-9);
  // 2.007640·0.298858^0.74 = 2.007640·0.409114 = 0.821354 → Fc = 1223.8 N, 0.1 % above 90°'s.
  EXPECT_NEAR(f.Pz, 1223.8, 0.05);
  EXPECT_THROW((void)model("steel_45", ForceForm::Kienzle, 95.5), std::invalid_argument);
}

TEST(CuttingModel, HandbookAndKienzleAgreeForSteel45) {
  // Two independent data sources for the same steel: Pz (handbook) = 1218.97 N and
  // Fc (Kienzle, κ = 90°) = 1222.6 N. They must agree within 25 %.
  const double hb = model("steel_45").forces(kRef).Pz;
  const double kz = model("steel_45", ForceForm::Kienzle, 90.0).forces(kRef).Pz;
  EXPECT_LT(std::abs(hb - kz) / hb, 0.25);
}

TEST(CuttingModel, ToolLifeRoundTripsWithSpeedForLife) {
  const auto cm = model("steel_45");
  // T = (Cv / (V·t^xv·s^yv))^(1/m); s = 0.2 ≤ 0.3 → Cv = 420, xv = 0.15, yv = 0.2, m = 0.2.
  const double T = cm.tool_life_min(150.0, 0.2, 2.0);
  const double expected = std::pow(420.0 / (150.0 * std::pow(2.0, 0.15) * std::pow(0.2, 0.2)), 5.0);
  EXPECT_NEAR(T, expected, 1e-9 * expected);
  // By hand: 2^0.15 = 1.109569, 0.2^0.2 = 0.724780 → 420/(150·0.804196) = 3.481734, ^5 = 511.67
  // min.
  EXPECT_NEAR(T, 511.67, 0.01);
  EXPECT_NEAR(cm.speed_for_life(T, 0.2, 2.0), 150.0, 1e-9);

  // And the other way: V for T = 60 min at t = 2, s = 0.2:
  // V = 420/(60^0.2·2^0.15·0.2^0.2) = 420/(2.267933·1.109569·0.724780) = 420/1.823876 = 230.28
  // m/min.
  const double v60 = cm.speed_for_life(60.0, 0.2, 2.0);
  EXPECT_NEAR(v60, 230.28, 0.01);
  EXPECT_NEAR(cm.tool_life_min(v60, 0.2, 2.0), 60.0, 1e-9);

  // Faster cutting, shorter life (T ∝ V^(−1/m) = V^−5).
  EXPECT_NEAR(cm.tool_life_min(300.0, 0.2, 2.0) / T, std::pow(2.0, -5.0), 1e-12);
}

TEST(CuttingModel, ToolLifeFeedRangesPickTheRightCv) {
  const auto cm = model("steel_45");
  const double T = 60.0, t = 2.0;
  auto v = [&](double cv, double yv, double s) {
    return cv / (std::pow(T, 0.2) * std::pow(t, 0.15) * std::pow(s, yv));
  };
  // Handbook, steel 45: s ≤ 0.3: Cv=420, yv=0.2; 0.3–0.7: Cv=350, yv=0.35; > 0.7: Cv=340, yv=0.45.
  EXPECT_NEAR(cm.speed_for_life(T, 0.1, t), v(420.0, 0.20, 0.1), 1e-9);
  EXPECT_NEAR(cm.speed_for_life(T, 0.3, t), v(420.0, 0.20, 0.3), 1e-9);  // boundary: first range
  EXPECT_NEAR(cm.speed_for_life(T, 0.31, t), v(350.0, 0.35, 0.31), 1e-9);
  EXPECT_NEAR(cm.speed_for_life(T, 0.7, t), v(350.0, 0.35, 0.7), 1e-9);
  EXPECT_NEAR(cm.speed_for_life(T, 0.8, t), v(340.0, 0.45, 0.8), 1e-9);
  EXPECT_NEAR(cm.speed_for_life(T, 2.0, t), v(340.0, 0.45, 2.0), 1e-9);
  // Tool life round trip in each range.
  for (const double s : {0.1, 0.5, 1.2})
    EXPECT_NEAR(cm.tool_life_min(cm.speed_for_life(T, s, t), s, t), T, 1e-9);
}

TEST(CuttingModel, ToolLifeFallsWithHardnessByTheHandbookKmv) {
  // Kosilova & Meshcheryakov vol. 2, turning, speed corrections: Kmv = Kг·(750/σв)^nv, nv = 1.0
  // for steel with carbide (data/materials.toml: kmv_exponent). A local factor h acts as σв·h:
  // V_T ∝ h^(−1), and at one speed T ∝ Kmv^(1/m) = h^(−5) (m = 0.2).
  const auto cm = model("steel_45");
  EXPECT_DOUBLE_EQ(cm.params().material.kmv_exponent, 1.0);
  const double T1 = cm.tool_life_min(150.0, 0.5, 3.0);
  EXPECT_NEAR(cm.tool_life_min(150.0, 0.5, 3.0, 1.3) / T1, std::pow(1.3, -5.0), 1e-12);
  EXPECT_NEAR(cm.speed_for_life(60.0, 0.5, 3.0, 1.3) / cm.speed_for_life(60.0, 0.5, 3.0), 1 / 1.3,
              1e-12);
  EXPECT_DOUBLE_EQ(cm.tool_life_min(150.0, 0.5, 3.0, 1.0), T1);  // h = 1: the table itself
  // The 40Kh table is the 45 table × (750/980)^1 (its comment): the same law at h = 980/750.
  const auto k40 = model("steel_40Kh");
  EXPECT_NEAR(k40.speed_for_life(60.0, 0.5, 3.0) / cm.speed_for_life(60.0, 0.5, 3.0, 980.0 / 750.0),
              1.0, 0.005);
  // Grey cast iron, nv = 1.25.
  const auto ci = model("cast_iron_SCh20");
  EXPECT_NEAR(ci.tool_life_min(100.0, 0.3, 2.0, 1.2) / ci.tool_life_min(100.0, 0.3, 2.0),
              std::pow(1.2, -1.25 / 0.2), 1e-12);
}

TEST(CuttingModel, ToolLifeInfiniteWhenNotCutting) {
  const auto cm = model("steel_45");
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(cm.tool_life_min(0.0, 0.2, 2.0), inf);
  EXPECT_EQ(cm.tool_life_min(150.0, 0.0, 2.0), inf);
  EXPECT_EQ(cm.tool_life_min(150.0, 0.2, 0.0), inf);
  EXPECT_EQ(cm.speed_for_life(0.0, 0.2, 2.0), 0.0);
}

TEST(CuttingModel, TheoreticalRoughness) {
  const auto cm = model("steel_45", ForceForm::Handbook, 90.0, 0.8);
  // Rz = s²/(8r) = 0.2²/(8·0.8) = 0.04/6.4 = 0.00625 mm = 6.25 µm; Ra ≈ s²/(32r) = 1.5625 µm.
  EXPECT_NEAR(cm.roughness_Rz_um(0.2), 6.25, 1e-12);
  EXPECT_NEAR(cm.roughness_Ra_um(0.2), 1.5625, 1e-12);
  const auto cm2 = model("steel_45", ForceForm::Handbook, 90.0, 1.2);
  // 0.3²/(8·1.2) = 0.009375 mm.
  EXPECT_NEAR(cm2.roughness_Rz_um(0.3), 9.375, 1e-12);
}

TEST(CuttingModel, ConfigureRejectsBadParameters) {
  const Material m = *library().find("steel_45");
  CuttingModel cm;
  EXPECT_THROW(cm.configure({m, ForceForm::Handbook, 0.0, 0.8}), std::invalid_argument);
  EXPECT_THROW(cm.configure({m, ForceForm::Handbook, 95.5, 0.8}), std::invalid_argument);
  EXPECT_THROW(cm.configure({m, ForceForm::Handbook, 90.0, 0.0}), std::invalid_argument);
  Material bad = m;
  bad.strength = 0.0;
  EXPECT_THROW(cm.configure({bad, ForceForm::Handbook, 90.0, 0.8}), std::invalid_argument);
  bad = m;
  bad.Py.Cp = 0.0;
  EXPECT_THROW(cm.configure({bad, ForceForm::Handbook, 90.0, 0.8}), std::invalid_argument);
  bad = m;
  bad.Fc.k11_N_per_mm2 = 0.0;
  EXPECT_THROW(cm.configure({bad, ForceForm::Kienzle, 90.0, 0.8}), std::invalid_argument);
  EXPECT_NO_THROW(cm.configure({bad, ForceForm::Handbook, 90.0, 0.8}));  // Kienzle data unused
}

}  // namespace
}  // namespace lathectl::cutting
