// Design calculator of seed 000 (include/lathectl/design/pulse_regulator.hpp) against an example
// worked by hand.
//
// Input: d = 8 mm, h = 0.04 mm, Δp = 0.5 MPa, ρ = 870 kg/m³, μ = 0.65, Δt = 10 ms, T = 50 ms,
//        F = 20 cm², K_leak = 50 cm³/min/MPa, Py = 1000 N, ΔPy = 500 N.
// Conversions: K_leak = 50e−6 m³ / 60 s / 1e6 Pa = 8.3333e−13 m³/(s·Pa); F = 20e−4 m².
//   sqrt(2Δp/ρ) = sqrt(1e6/870) = sqrt(1149.425) = 33.9032 m/s
//   μπd = 0.65·3.141593·0.008 = 0.0163363 m
//   base = μπd·sqrt(2Δp/ρ) = 0.553852 m²/s
//   duty = Δt/T = 0.2, f = 20 Hz
//   (2) Ka = 0.553852·0.2 = 0.110770 m²/s
//   (1) Q = Ka·h = 0.110770·4e−5 = 4.43081e−6 m³/s = 265.85 cm³/min
//   (6) Kf = 0.553852·4e−5·0.01 = 2.21541e−7 m³
//   (3) S = Q/F − K·Py/F² = 2.21541e−3 − 8.3333e−13·1000/4e−6 = 2.21541e−3 − 2.08333e−4
//         = 2.00707e−3 m/s = 120.42 mm/min
//   (4) Δh = K·ΔPy/(Ka·F) = 4.16667e−10/(0.110770·2e−3) = 1.88077e−6 m = 1.881 µm
//       Δf = K·ΔPy/(Kf·F) = 4.16667e−10/(2.21541e−7·2e−3) = 0.94038 Hz

#include "lathectl/design/pulse_regulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace lathectl::design {
namespace {

PulseRegulatorInput example() {
  PulseRegulatorInput in;
  in.spool_diameter_m = 8e-3;
  in.slot_m = 0.04e-3;
  in.pressure_drop_Pa = 0.5e6;
  in.density_kg_per_m3 = 870.0;
  in.discharge_coefficient = 0.65;
  in.pulse_width_s = 10e-3;
  in.period_s = 50e-3;
  in.piston_area_m2 = 20e-4;
  in.leak_m3_per_s_Pa = 50e-6 / 60.0 / 1e6;
  in.force_N = 1000.0;
  in.force_change_N = 500.0;
  return in;
}

TEST(DesignPulseRegulator, HandWorkedExample) {
  const auto r = pulse_regulator(example());
  EXPECT_NEAR(r.duty, 0.2, 1e-15);
  EXPECT_NEAR(r.frequency_Hz, 20.0, 1e-12);
  EXPECT_NEAR(r.ka_m2_per_s, 0.110770, 1e-6);
  EXPECT_NEAR(r.flow_m3_per_s, 4.43081e-6, 1e-10);
  EXPECT_NEAR(r.flow_m3_per_s * 6e7, 265.85, 0.01);  // cm³/min
  EXPECT_NEAR(r.kf_m3, 2.21541e-7, 1e-11);
  EXPECT_NEAR(r.feed_m_per_s, 2.00707e-3, 1e-8);
  EXPECT_NEAR(r.feed_m_per_s * 6e4, 120.42, 0.01);  // mm/min
  EXPECT_NEAR(r.feed_no_leak_m_per_s, 2.21541e-3, 1e-8);
  EXPECT_NEAR(r.leak_m3_per_s, 4.16667e-7, 1e-11);  // K·Py/F = 8.3333e−13·1000/20e−4 m³/s
  EXPECT_NEAR(r.slot_change_m, 1.88077e-6, 1e-11);
  EXPECT_NEAR(r.frequency_change_Hz, 0.94038, 1e-5);
}

TEST(DesignPulseRegulator, MatchesFormulasEvaluatedIndependently) {
  const auto in = example();
  const auto r = pulse_regulator(in);
  const double base = 0.65 * std::numbers::pi * 8e-3 * std::sqrt(2.0 * 0.5e6 / 870.0);
  const double Ka = base * 0.2, Kf = base * 0.04e-3 * 10e-3, F = 20e-4, K = in.leak_m3_per_s_Pa;
  EXPECT_NEAR(r.ka_m2_per_s, Ka, 1e-12 * Ka);                                   // (2)
  EXPECT_NEAR(r.flow_m3_per_s, Ka * 0.04e-3, 1e-12 * Ka * 0.04e-3);             // (1)
  EXPECT_NEAR(r.kf_m3, Kf, 1e-12 * Kf);                                         // (6)
  EXPECT_NEAR(r.flow_m3_per_s, Kf * 20.0, 1e-12 * Kf * 20.0);                   // (6): Q = Kf·f
  EXPECT_NEAR(r.feed_m_per_s, Ka * 0.04e-3 / F - K * 1000.0 / (F * F), 1e-15);  // (3)
  EXPECT_NEAR(r.slot_change_m, K * 500.0 / (Ka * F), 1e-18);                    // (4)
  EXPECT_NEAR(r.frequency_change_Hz, K * 500.0 / (Kf * F), 1e-12);
}

TEST(DesignPulseRegulator, Formula4RestoresFormula5) {
  // (5): S = Q/F − K(Py + ΔPy)/F² + Ka·Δh/F must equal the feed before the change:
  // the slot correction's flow Ka·Δh/F equals the extra leakage K·ΔPy/F².
  for (const double dP : {10.0, 500.0, 2500.0}) {
    auto in = example();
    in.force_change_N = dP;
    const auto r = pulse_regulator(in);
    const double F = in.piston_area_m2, K = in.leak_m3_per_s_Pa;
    EXPECT_NEAR(r.ka_m2_per_s * r.slot_change_m / F, K * dP / (F * F), 1e-12 * K * dP / (F * F));
    // The FIM counterpart: Kf·Δf/F = K·ΔPy/F².
    EXPECT_NEAR(r.kf_m3 * r.frequency_change_Hz / F, K * dP / (F * F), 1e-12 * K * dP / (F * F));
    // The corrected slot, fed to (2) and (3) at Py + ΔPy, gives back the original feed.
    auto after = in;
    after.slot_m = in.slot_m + r.slot_change_m;
    after.force_N = in.force_N + dP;
    EXPECT_NEAR(pulse_regulator(after).feed_m_per_s, r.feed_m_per_s, 1e-12 * r.feed_m_per_s);
  }
}

TEST(DesignPulseRegulator, FlowIndependentOfSlotPrecisionAtFixedDuty) {
  // Claim 4: the mean flow is set by Δt/T; halving the period and the pulse together keeps it.
  auto a = example();
  auto b = example();
  b.pulse_width_s = 5e-3;
  b.period_s = 25e-3;
  EXPECT_NEAR(pulse_regulator(a).flow_m3_per_s, pulse_regulator(b).flow_m3_per_s, 1e-18);
  EXPECT_NEAR(pulse_regulator(b).frequency_Hz, 40.0, 1e-12);
}

TEST(DesignPulseRegulator, ZeroLeakageNeedsNoCorrection) {
  auto in = example();
  in.leak_m3_per_s_Pa = 0.0;
  const auto r = pulse_regulator(in);
  EXPECT_EQ(r.slot_change_m, 0.0);
  EXPECT_EQ(r.frequency_change_Hz, 0.0);
  EXPECT_DOUBLE_EQ(r.feed_m_per_s, r.feed_no_leak_m_per_s);
}

TEST(DesignPulseRegulator, InvalidInputsThrow) {
  auto bad = [](auto edit) {
    auto in = example();
    edit(in);
    EXPECT_THROW((void)pulse_regulator(in), std::invalid_argument);
  };
  bad([](PulseRegulatorInput& in) { in.spool_diameter_m = 0.0; });
  bad([](PulseRegulatorInput& in) { in.slot_m = -1e-5; });
  bad([](PulseRegulatorInput& in) { in.pressure_drop_Pa = 0.0; });
  bad([](PulseRegulatorInput& in) { in.density_kg_per_m3 = 0.0; });
  bad([](PulseRegulatorInput& in) { in.pulse_width_s = 0.0; });
  bad([](PulseRegulatorInput& in) { in.period_s = 0.0; });
  bad([](PulseRegulatorInput& in) { in.piston_area_m2 = 0.0; });
  bad([](PulseRegulatorInput& in) { in.discharge_coefficient = 0.0; });
  bad([](PulseRegulatorInput& in) { in.discharge_coefficient = 1.1; });
  bad([](PulseRegulatorInput& in) { in.leak_m3_per_s_Pa = -1e-13; });
  bad([](PulseRegulatorInput& in) { in.pulse_width_s = 60e-3; });  // Δt > T
  bad([](PulseRegulatorInput& in) {
    in.spool_diameter_m = std::numeric_limits<double>::quiet_NaN();
  });
  bad([](PulseRegulatorInput& in) { in.period_s = std::numeric_limits<double>::infinity(); });
  bad([](PulseRegulatorInput& in) {
    in.leak_m3_per_s_Pa = std::numeric_limits<double>::quiet_NaN();
  });
}

}  // namespace
}  // namespace lathectl::design
