// The lobes machine file (src/systems/b_chatter/lobes.hpp): [[mode]]s alone as before, a
// [part] between centres with or without tool modes, and located errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/io/errors.hpp"
#include "systems/b_chatter/lobes.hpp"

using namespace lathectl;

namespace {
const std::string kHead =
    "[cutting]\nkf_N_per_mm2 = 2000\n[speed]\nmin_rpm = 1200\nmax_rpm = 3000\n";
const std::string kPart =
    "[part]\nlength_mm = 500\ndiameter_mm = 30\nyoungs_modulus_GPa = 210\n"
    "density_kg_per_m3 = 7850\ndamping_ratio = 0.02\nposition_mm = 100\n";
const std::string kTool =
    "[[mode]]\nstiffness_N_per_m = 5e7\ndamping_ratio = 0.03\nnatural_frequency_Hz = 800\n";
}  // namespace

TEST(LobesInput, ModesAloneAsBefore) {
  const auto in = b_chatter::parse_lobes_input(kHead + kTool, "m.toml");
  ASSERT_EQ(in.system.modes.size(), 1u);
  EXPECT_FALSE(in.part.has_value());
  EXPECT_DOUBLE_EQ(in.system.modes[0].natural_frequency_Hz, 800.0);
  EXPECT_DOUBLE_EQ(in.system.kf_N_per_m2, 2e9);
  EXPECT_EQ(in.chart_speeds, 200);
  EXPECT_EQ(in.chart_depths, 100);
}

// The part's modes at the cutting position come first, the tool's are added: the relative
// tool–part displacement is the sum of both receptances.
TEST(LobesInput, PartAndToolModesAtTheCuttingPosition) {
  const auto in = b_chatter::parse_lobes_input(kHead + kPart + kTool, "m.toml");
  ASSERT_TRUE(in.part.has_value());
  EXPECT_EQ(in.part->modes, 3);
  EXPECT_DOUBLE_EQ(in.part->beam.youngs_modulus_Pa, 210e9);
  const auto beam = dynamics::beam_modes_at(in.part->beam, 0.1, 3);
  ASSERT_EQ(in.system.modes.size(), beam.size() + 1);
  for (std::size_t i = 0; i < beam.size(); ++i)
    EXPECT_DOUBLE_EQ(in.system.modes[i].stiffness_N_per_m, beam[i].stiffness_N_per_m);
  EXPECT_DOUBLE_EQ(in.system.modes.back().stiffness_N_per_m, 5e7);
  const auto mid = b_chatter::lobes_system_at(in, 0.25);
  EXPECT_EQ(mid.modes.size(), 3u);  // mode 2 has a node mid-span
}

// The SD chart resolves the mode that can chatter, not the part's stiff third mode at 9·f1.
TEST(LobesInput, ChartStepsFollowTheChatteringMode) {
  auto in = b_chatter::parse_lobes_input(kHead + kPart, "m.toml");
  const auto sys = b_chatter::lobes_system_at(in, 0.25);
  const double f1 = sys.modes[0].natural_frequency_Hz;
  EXPECT_EQ(dynamics::sd_steps_per_delay(sys, 1200.0, 0.27e-3),
            static_cast<int>(std::ceil(0.05 * f1 * dynamics::SdChartOptions{}.steps_per_period)));
}

TEST(LobesInput, LocatedErrors) {
  auto message = [](const std::string& text) {
    try {
      (void)b_chatter::parse_lobes_input(text, "m.toml");
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(kHead).find("at least one [[mode]] or a [part]"), std::string::npos);
  EXPECT_NE(message(kHead + kPart + "speed_rpm = 3\n").find("unknown key 'part.speed_rpm'"),
            std::string::npos);
  std::string outside = kPart;
  outside.replace(outside.find("position_mm = 100"), 17, "position_mm = 600");
  EXPECT_NE(message(kHead + outside).find("m.toml:"), std::string::npos);
  EXPECT_NE(message(kHead + outside).find("'part.position_mm'"), std::string::npos);
  EXPECT_NE(message(kHead + kPart + "positions_mm = [100, 0]\n").find("'part.positions_mm'"),
            std::string::npos);
  EXPECT_NE(message(kHead + kTool + "[lobes]\nchart_depths = 1\n").find("'lobes.chart_depths'"),
            std::string::npos);
}

TEST(LobesInput, EveryKeyOfTheMachineFileIsDescribed) {
  const auto rows = b_chatter::describe_machine_file();
  std::size_t keys = 0;
  for (const auto& r : rows) {
    if (r.kind == "table" || r.kind == "array of tables") continue;
    ++keys;
    EXPECT_FALSE(r.doc.empty()) << r.key;
  }
  EXPECT_EQ(keys, 22u);  // cutting 1, mode 4, part 9, speed 2, lobes 6
}
