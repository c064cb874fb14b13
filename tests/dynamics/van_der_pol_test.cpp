// The quenching condition behind seed 001's modulated feed, checked on a van der Pol oscillator.
#include "lathectl/dynamics/van_der_pol.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace lathectl::dynamics;

// Unforced: the limit cycle of ẍ − ε(1 − x²)ẋ + x = 0 has amplitude a0 = 2 + O(ε²).
TEST(VanDerPol, LimitCycleAmplitudeIsTwo) {
  EXPECT_NEAR(van_der_pol_forced(0.1, 5.0, 0.0).self_amplitude, 2.0, 0.01);
}

// First-order averaging: ȧ = (ε/2)·a·(1 − B²/2 − a²/4), quenching for B > a0/√2 = √2.
// Measured (forcing at Ω = 5, far from any combination resonance): within 1 %.
TEST(VanDerPol, QuenchingThresholdIsA0OverRootTwo) {
  for (double eps : {0.05, 0.1, 0.3}) {
    const double a0 = van_der_pol_forced(eps, 5.0, 0.0).self_amplitude;
    const double b = quenching_threshold(eps, 5.0);
    EXPECT_NEAR(b / (a0 / std::sqrt(2.0)), 1.0, 0.01) << "ε = " << eps;
    // The seed's condition 1.41·a0 is twice the measured threshold: a 2× margin.
    EXPECT_NEAR(1.41 * a0 / b, 2.0, 0.03) << "ε = " << eps;
  }
}

// Above the threshold the self-excited part dies; below it survives at a reduced amplitude
// a = 2·sqrt(1 − B²/2).
TEST(VanDerPol, BelowThresholdTheCycleSurvivesReduced) {
  const double W = 5.0, B = 1.0, E = B * (W * W - 1.0);
  const auto q = van_der_pol_forced(0.3, W, -E, 400.0, 0.5);
  EXPECT_NEAR(q.self_amplitude, 2.0 * std::sqrt(1.0 - B * B / 2.0), 0.05);
  const auto quenched = van_der_pol_forced(0.3, W, -1.8 * (W * W - 1.0), 400.0, 0.5);
  EXPECT_LT(quenched.self_amplitude, 0.01);
}
