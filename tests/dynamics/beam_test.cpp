// Slender part between centres: modes seen at the tool.
#include "lathectl/dynamics/beam.hpp"

#include <gtest/gtest.h>

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
