// core::FirstOrderLag: the one first-order lag. Its forms are the arithmetic the models and
// controllers had written out (bit for bit), and each is exact for the input it assumes.

#include "lathectl/core/first_order_lag.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace lathectl::core {
namespace {

TEST(FirstOrderLag, TheFormsAreTheWrittenOutArithmetic) {
  const double dt = 1e-3, tau = 0.0137;
  const FirstOrderLag lag(dt, tau);
  const double d = std::exp(-dt / tau), a = 1.0 - std::exp(-dt / tau);
  double y = 0.3, z = 0.3;
  for (int i = 0; i < 1000; ++i) {
    const double x = std::sin(0.01 * i) * 7.0;
    EXPECT_EQ(lag.step(y, x), x + (y - x) * d);
    EXPECT_EQ(lag.step_increment(z, x), z + a * (x - z));
    y = lag.step(y, x);
    z = lag.step_increment(z, x);
  }
  EXPECT_EQ(lag.decay(), d);
  EXPECT_EQ(lag.gain(), a);
  const double r = tau / dt, x0 = 1.0, x1 = 2.5;
  EXPECT_EQ(lag.step_ramp(y, x0, x1, r), x1 - (x1 - x0) * r + (y - x0 + (x1 - x0) * r) * d);
}

TEST(FirstOrderLag, NoTimeConstantIsNoLag) {
  for (const FirstOrderLag lag : {FirstOrderLag(), FirstOrderLag(1e-3, 0.0),
                                  FirstOrderLag(1e-3, -1.0)}) {
    EXPECT_EQ(lag.decay(), 0.0);
    EXPECT_EQ(lag.gain(), 1.0);
    EXPECT_EQ(lag.step(3.0, 5.0), 5.0);
    EXPECT_EQ(lag.step_increment(3.0, 5.0), 5.0);
  }
}

TEST(FirstOrderLag, ExactForItsInputAtAnyStep) {
  // A step input: y(t) = x + (y0 − x)·e^(−t/τ), whatever the step, even Δt ≫ τ (forward Euler
  // would oscillate there).
  const double tau = 0.02, x = 4.0, y0 = 1.0, t = 0.1;
  for (int n : {1, 3, 10, 1000}) {
    const FirstOrderLag lag(t / n, tau);
    double y = y0, z = y0;
    for (int i = 0; i < n; ++i) {
      y = lag.step(y, x);
      z = lag.step_increment(z, x);
    }
    EXPECT_NEAR(y, x + (y0 - x) * std::exp(-t / tau), 1e-12) << n;
    EXPECT_NEAR(z, y, 1e-12) << n;
  }
  // A ramp x = k·t from y0 = 0: y(t) = k·(t − τ + τ·e^(−t/τ)).
  const double k = 3.0;
  for (int n : {1, 7, 100}) {
    const double h = t / n;
    const FirstOrderLag lag(h, tau);
    double y = 0.0;
    for (int i = 0; i < n; ++i) y = lag.step_ramp(y, k * h * i, k * h * (i + 1), tau / h);
    EXPECT_NEAR(y, k * (t - tau + tau * std::exp(-t / tau)), 1e-12) << n;
  }
}

TEST(FirstOrderLag, FromADecay) {
  const double f = 40.0, dt = 1e-4, kPi = 3.141592653589793;
  const auto lag = FirstOrderLag::with_decay(std::exp(-2.0 * kPi * f * dt));
  EXPECT_EQ(lag.gain(), 1.0 - std::exp(-2.0 * kPi * f * dt));
  EXPECT_NEAR(lag.decay(), FirstOrderLag(dt, 1.0 / (2.0 * kPi * f)).decay(), 1e-15);
}

}  // namespace
}  // namespace lathectl::core
