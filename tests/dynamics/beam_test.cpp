// Slender part between centres: modes seen at the tool.
#include "lathectl/dynamics/beam.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cmath>
#include <numbers>

using namespace lathectl::dynamics;

// Pinned-pinned Euler–Bernoulli beam, first frequency f1 = (π/2L²)·sqrt(EI/ρA) (e.g. Blevins,
// "Formulas for natural frequency and mode shape", table 8-1). Steel Ø30 × 500 mm:
// I = π·0.03⁴/64 = 3.976e-8 m⁴, A = 7.069e-4 m², sqrt(EI/ρA) = sqrt(8350/5.549) = 38.79 m²/s,
// f1 = π/(2·0.25)·38.79 = 243.7 Hz.
TEST(Beam, FirstFrequencyMatchesHandbook) {
  const BeamPart part;
  const auto modes = beam_modes_at(part, 0.25, 3);
  ASSERT_EQ(modes.size(), 2u);  // mode 2 has a node mid-span
  EXPECT_NEAR(modes[0].natural_frequency_Hz, 243.7, 0.5);
  EXPECT_NEAR(modes[1].natural_frequency_Hz / modes[0].natural_frequency_Hz, 9.0, 1e-9);  // mode 3
}

// Mid-span, mode 1 dominates the static compliance: k1 = ρAL/2·ω1² against the static 48EI/L³
// (the series of all modes sums to it; mode 1 alone gives π⁴/96 ≈ 1.015 of the stiffness).
TEST(Beam, ModalStiffnessMidSpanAgainstStatic) {
  const BeamPart part;
  const auto modes = beam_modes_at(part, 0.25, 1);
  EXPECT_NEAR(modes[0].stiffness_N_per_m / beam_static_stiffness(part, 0.25),
              std::pow(std::numbers::pi, 4) / 96.0, 1e-9);
}

// Near a centre the part is far stiffer: the mode's stiffness seen at the tool is k1/sin²(πx/L).
TEST(Beam, StiffNearTheCentres) {
  const BeamPart part;
  const double mid = beam_modes_at(part, 0.25, 1)[0].stiffness_N_per_m;
  const double near = beam_modes_at(part, 0.05, 1)[0].stiffness_N_per_m;
  EXPECT_NEAR(near / mid, 1.0 / std::pow(std::sin(std::numbers::pi * 0.05 / 0.5), 2), 1e-9);
  EXPECT_THROW(beam_modes_at(part, 0.0, 1), std::invalid_argument);
}

// The chatter limit follows the cutting position: lower mid-span than near a centre.
TEST(Beam, ChatterLimitDependsOnPosition) {
  BeamPart part;
  ChatterSystem mid{beam_modes_at(part, 0.25, 3), 2e9}, near{beam_modes_at(part, 0.05, 3), 2e9};
  const auto a = frequency_domain_lobes(mid, 500, 5000, 40, 4000);
  const auto b = frequency_domain_lobes(near, 500, 5000, 40, 4000);
  EXPECT_LT(a.critical_depth_m, 0.2 * b.critical_depth_m);
}

// Along the part with its first mode alone, the absolute limit follows the SDOF closed form with
// the stiffness seen at the tool: b(x) = 2·k1·ζ(1+ζ)/(K_f·sin²(πx/L)) (Altintas, eq. 3.30, with
// the modal stiffness of mode 1, k1 = ρAL/2·ω1²), i.e. 1/sin²(πx/L) times the mid-span value.
TEST(Beam, ChatterLimitAlongThePartFollowsTheModeShape) {
  const BeamPart part;
  const double kf = 2e9, zeta = part.damping_ratio;
  const double k1 = beam_modes_at(part, 0.25, 1)[0].stiffness_N_per_m;
  for (double x : {0.02, 0.1, 0.25, 0.4}) {
    const ChatterSystem sys{beam_modes_at(part, x, 1), kf};
    const auto fd = frequency_domain_lobes(sys, 500, 5000, 60, 4000);
    const double s = std::sin(std::numbers::pi * x / part.length_m);
    EXPECT_NEAR(fd.critical_depth_m / (2.0 * k1 * zeta * (1.0 + zeta) / (kf * s * s)), 1.0, 1e-6)
        << "x = " << x;
  }
}

// Set-ups beyond centres (finite elements, dynamics/beam.hpp) against the closed-form
// Euler–Bernoulli frequencies ω = (βL)²·√(EI/(ρAL⁴)); βL from the characteristic equations
// (Blevins, "Formulas for Natural Frequency and Mode Shape", 1979, table 8-1):
//   clamped–free   cos βL·cosh βL = −1:      1.875104, 4.694091, 7.854757
//   clamped–pinned tan βL = tanh βL:         3.926602, 7.068583, 10.210176
//   pinned–pinned  sin βL = 0:               π, 2π, 3π
// and, with a steady rest at mid-span between centres, two pinned–pinned spans of L/2: the
// first mode antisymmetric (βL = 2π), the second each half clamped–pinned by symmetry
// (βL = 2·3.926602); a cantilever with its rest at the free end is clamped–pinned.
TEST(BeamSetups, ClosedFormFrequenciesOfEachBoundaryCondition) {
  BeamPart p;
  p.length_m = 0.4;
  p.diameter_m = 0.04;
  const double pi = std::numbers::pi;
  const double area = pi * p.diameter_m * p.diameter_m / 4.0;
  const double EI = p.youngs_modulus_Pa * pi * std::pow(p.diameter_m, 4) / 64.0;
  const double c = std::sqrt(EI / (p.density_kg_per_m3 * area)) / std::pow(p.length_m, 2);
  struct Case {
    const char* name;
    BeamSupports s;
    std::vector<double> betaL;
  };
  const std::vector<Case> cases{
      {"chuck", {BeamEnd::clamped, BeamEnd::free, 0.0}, {1.875104, 4.694091, 7.854757}},
      {"chuck and tailstock", {BeamEnd::clamped, BeamEnd::pinned, 0.0}, {3.926602, 7.068583, 10.210176}},
      {"between centres", {BeamEnd::pinned, BeamEnd::pinned, 0.0}, {pi, 2 * pi, 3 * pi}},
      {"centres, rest mid-span", {BeamEnd::pinned, BeamEnd::pinned, 0.2}, {2 * pi, 2 * 3.926602}},
      {"chuck, rest at the end", {BeamEnd::clamped, BeamEnd::free, 0.4}, {3.926602, 7.068583}},
  };
  for (const auto& k : cases) {
    const auto m = beam_model(p, k.s, 3);
    for (std::size_t j = 0; j < k.betaL.size(); ++j) {
      const double exact = k.betaL[j] * k.betaL[j] * c;
      std::printf("%-24s mode %zu: %.3f Hz, closed form %.3f Hz (%+.2e)\n", k.name, j + 1,
                  m.omega_rad_s[j] / (2 * pi), exact / (2 * pi), m.omega_rad_s[j] / exact - 1);
      EXPECT_NEAR(m.omega_rad_s[j] / exact, 1.0, 1e-5) << k.name << " mode " << j + 1;
    }
  }
}

// Between centres the elements reproduce the analytic pinned–pinned modes seen at the tool
// (stiffness ω²/φ² and frequency), and the static stiffness 3EIL/(x²(L−x)²); a cantilever's
// static stiffness at x is 3EI/x³.
TEST(BeamSetups, CentresAsTheAnalyticBeamAndStaticStiffness) {
  BeamPart p;  // Ø30 × 500 mm steel, as examples/machines/b_part.toml
  p.length_m = 0.5;
  p.diameter_m = 0.03;
  const auto m = beam_model(p, {}, 3);
  for (const double x : {0.1, 0.25, 0.37}) {
    const auto fe = beam_model_modes_at(m, x);
    const auto an = beam_modes_at(p, x, 3);
    ASSERT_EQ(fe.size(), an.size()) << x;
    for (std::size_t j = 0; j < an.size(); ++j) {
      EXPECT_NEAR(fe[j].natural_frequency_Hz / an[j].natural_frequency_Hz, 1.0, 1e-5);
      EXPECT_NEAR(fe[j].stiffness_N_per_m / an[j].stiffness_N_per_m, 1.0, 1e-4);
    }
    EXPECT_NEAR(beam_model_static_stiffness(m, x) / beam_static_stiffness(p, x), 1.0, 1e-6);
  }
  const auto cant = beam_model(p, {BeamEnd::clamped, BeamEnd::free, 0.0}, 3);
  const double EI = p.youngs_modulus_Pa * std::numbers::pi * std::pow(p.diameter_m, 4) / 64.0;
  for (const double x : {0.1, 0.3, 0.5})
    EXPECT_NEAR(beam_model_static_stiffness(cant, x) / (3 * EI / (x * x * x)), 1.0, 1e-6) << x;
  EXPECT_THROW((void)beam_model(p, {BeamEnd::pinned, BeamEnd::free, 0.0}, 3), std::invalid_argument);
}
