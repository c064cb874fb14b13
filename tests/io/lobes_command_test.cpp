// The lobes machine file (src/systems/b_chatter/lobes.hpp): [[mode]]s alone as before, a
// [part] between centres with or without tool modes, and located errors.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <numbers>
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
  const auto in = systems::b_chatter::parse_lobes_input(kHead + kTool, "m.toml");
  ASSERT_EQ(in.system.modes.size(), 1u);
  EXPECT_FALSE(in.part.has_value());
  EXPECT_DOUBLE_EQ(in.system.modes[0].natural_frequency_Hz, 800.0);
  EXPECT_DOUBLE_EQ(in.system.kf_N_per_m2, 2e9);
  EXPECT_EQ(in.chart_speeds, 200);
  EXPECT_EQ(in.chart_depths, 100);
}

// [process_damping] gives the lobes C = 60·K_sp·VB²/(4π·D·sin κ) (dynamics/lobes.hpp), D the
// cutting diameter, and turns semi-discretization off (it has no process damping). Here
// K_sp = 4e4 N/mm³ = 4e13 N/m³, VB = 0.15 mm, D = 60 mm, κ = 75°.
TEST(LobesInput, ProcessDampingGivesTheLobesItsCoefficient) {
  const auto in = systems::b_chatter::parse_lobes_input(
      "[cutting]\nkf_N_per_mm2 = 2000\ndiameter_mm = 60\n[speed]\nmin_rpm = 1200\n"
      "max_rpm = 3000\n" + kTool +
          "[process_damping]\nk_sp_N_per_mm3 = 4e4\nwear_land_mm = 0.15\n"
          "approach_angle_deg = 75\n",
      "m.toml");
  const double C = 60.0 * 4e13 * 0.15e-3 * 0.15e-3 /
                   (4.0 * std::numbers::pi * 0.06 * std::sin(75.0 * std::numbers::pi / 180.0));
  EXPECT_NEAR(in.process_damping_C, C, 1e-9 * C);
  EXPECT_NEAR(in.system.process_damping_C, C, 1e-9 * C);
  EXPECT_EQ(in.modal.process_damping_C, 0.0);
  EXPECT_EQ(in.sd_speeds, 0);
  EXPECT_EQ(in.chart_speeds, 0);
  const auto plain = systems::b_chatter::parse_lobes_input(kHead + kTool, "m.toml");
  EXPECT_EQ(plain.system.process_damping_C, 0.0);
}

// The part's modes at the cutting position come first, the tool's are added: the relative
// tool–part displacement is the sum of both receptances.
TEST(LobesInput, PartAndToolModesAtTheCuttingPosition) {
  const auto in = systems::b_chatter::parse_lobes_input(kHead + kPart + kTool, "m.toml");
  ASSERT_TRUE(in.part.has_value());
  EXPECT_EQ(in.part->modes, 3);
  EXPECT_DOUBLE_EQ(in.part->beam.youngs_modulus_Pa, 210e9);
  const auto beam = dynamics::beam_modes_at(in.part->beam, 0.1, 3);
  ASSERT_EQ(in.system.modes.size(), beam.size() + 1);
  for (std::size_t i = 0; i < beam.size(); ++i)
    EXPECT_DOUBLE_EQ(in.system.modes[i].stiffness_N_per_m, beam[i].stiffness_N_per_m);
  EXPECT_DOUBLE_EQ(in.system.modes.back().stiffness_N_per_m, 5e7);
  const auto mid = systems::b_chatter::lobes_system_at(in, 0.25);
  EXPECT_EQ(mid.modes.size(), 3u);  // mode 2 has a node mid-span
}

// The SD chart resolves the mode that can chatter, not the part's stiff third mode at 9·f1.
TEST(LobesInput, ChartStepsFollowTheChatteringMode) {
  auto in = systems::b_chatter::parse_lobes_input(kHead + kPart, "m.toml");
  const auto sys = systems::b_chatter::lobes_system_at(in, 0.25);
  const double f1 = sys.modes[0].natural_frequency_Hz;
  EXPECT_EQ(dynamics::sd_steps_per_delay(sys, 1200.0, 0.27e-3),
            static_cast<int>(std::ceil(0.05 * f1 * dynamics::SdChartOptions{}.steps_per_period)));
}

TEST(LobesInput, LocatedErrors) {
  auto message = [](const std::string& text) {
    try {
      (void)systems::b_chatter::parse_lobes_input(text, "m.toml");
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(kHead).find("at least one [[mode]], [[frf]] or a [part]"), std::string::npos);
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
  const auto rows = systems::b_chatter::describe_machine_file();
  std::size_t keys = 0;
  for (const auto& r : rows) {
    if (r.kind == "table" || r.kind == "array of tables") continue;
    ++keys;
    EXPECT_FALSE(r.doc.empty()) << r.key;
  }
  EXPECT_EQ(keys, 38u);  // cutting 5, mode 4, frf 3, part 11, process_damping 3, speed 2,
                         // machine 2, recommend 2, lobes 6
}

// Every path from a machine file to "internal error", a crash or a hang ends in an
// InputError at file:line:col naming the key instead. The offending files are committed in
// fuzz/regressions/lobes/ (the CLI test runs each too).
namespace {
std::string regression_error(const std::string& name) {
  std::string path = LATHECTL_SOURCE_DIR;  // (one + chain trips GCC 12's -Warray-bounds)
  path += "/fuzz/regressions/lobes/";
  path += name;
  try {
    (void)systems::b_chatter::load_lobes_input(path);
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "no error";
}
bool located_at(const std::string& message, const std::string& file, const std::string& key) {
  const auto at = message.find(file + ":");
  return at != std::string::npos && message.find("key '" + key + "'") != std::string::npos;
}
}  // namespace

TEST(LobesInputHostile, PositionOnTheRightCentreIsLocated) {
  // 475·1e-3·1e3 rounds above 475: the range in mm let it through and the beam threw.
  const auto m = regression_error("position_on_centre.toml");
  EXPECT_TRUE(located_at(m, "position_on_centre.toml", "part.positions_mm")) << m;
  EXPECT_NE(m.find("position_on_centre.toml:12:"), std::string::npos) << m;
}

TEST(LobesInputHostile, PositionsNearACentreAreRefusedNotCrashed) {
  auto m = regression_error("position_near_centre.toml");
  EXPECT_TRUE(located_at(m, "position_near_centre.toml", "part.positions_mm")) << m;
  m = regression_error("cutting_position_near_centre.toml");
  EXPECT_TRUE(located_at(m, "cutting_position_near_centre.toml", "part.position_mm")) << m;
  // 1 % of the length from a centre is the edge of the range: accepted, every mode seen there.
  const auto in = systems::b_chatter::parse_lobes_input(
      kHead + kPart + "positions_mm = [5, 495]\n", "m.toml");
  for (double x : in.part->positions_m)
    EXPECT_EQ(dynamics::beam_modes_at(in.part->beam, x, 3).size(), 3u);
}

TEST(LobesInputHostile, DegenerateStiffnessAndPartAreRefused) {
  auto m = regression_error("stiffness_1e-300.toml");
  EXPECT_TRUE(located_at(m, "stiffness_1e-300.toml", "mode[0].stiffness_N_per_m")) << m;
  m = regression_error("part_1nm.toml");
  EXPECT_TRUE(located_at(m, "part_1nm.toml", "part.length_mm")) << m;
}

TEST(LobesInputHostile, WorkOverTheBoundsIsRefusedNamingTheKeys) {
  auto m = regression_error("speed_range_24GB.toml");
  EXPECT_TRUE(located_at(m, "speed_range_24GB.toml", "speed.min_rpm")) << m;
  m = regression_error("lobes_memory.toml");
  EXPECT_TRUE(located_at(m, "lobes_memory.toml", "speed.min_rpm")) << m;
  EXPECT_NE(m.find("GB"), std::string::npos) << m;
  m = regression_error("chart_hours.toml");
  EXPECT_TRUE(located_at(m, "chart_hours.toml", "lobes.chart_speeds")) << m;
  EXPECT_NE(m.find("coarser chart"), std::string::npos) << m;
}

// A 10⁶-cell chart is a valid input: its estimate is within the bounds.
TEST(LobesInputHostile, AMillionCellChartIsAccepted) {
  const auto in = systems::b_chatter::parse_lobes_input(
      kHead + kTool + "[lobes]\nchart_speeds = 1000\nchart_depths = 1000\n", "m.toml");
  const auto c = systems::b_chatter::lobes_cost(in, 2);
  EXPECT_DOUBLE_EQ(c.chart_cells, 1000.0 * (1000 + 17));
  EXPECT_LT(c.bytes, systems::b_chatter::kMaxBytes);
  EXPECT_LT(c.seconds, systems::b_chatter::kMaxSeconds);
}

// The estimate counts the frequency-domain points exactly (what the memory grows with).
TEST(LobesInputHostile, FrequencyDomainPointCountIsExact) {
  const auto in = systems::b_chatter::parse_lobes_input(kHead + kPart + kTool, "m.toml");
  const auto fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm,
                                                   in.max_lobes, 40000);
  double stored = 0.0;
  for (const auto& l : fd.lobes) stored += static_cast<double>(l.points.size());
  const double counted = dynamics::frequency_domain_point_count(in.system, in.min_rpm,
                                                                in.max_rpm, in.max_lobes, 40000);
  EXPECT_NEAR(counted, stored, 1e-3 * stored);
}

// A machine measured by tap tests (examples/machines/b_frf.toml: x/x CSV and y/y UFF 58, 2 %
// noise, chip 30° from x) against the modes that frf/make_frf.py wrote them from, oriented by
// hand: 250 Hz and 900 Hz along x weigh cos²30° = 0.75, 150 Hz along y sin²30° = 0.25.
TEST(LobesFrf, TapTestsAgainstTheirModes) {
  std::string path = LATHECTL_SOURCE_DIR;  // (one + chain trips GCC 12's -Warray-bounds)
  path += "/examples/machines/b_frf.toml";
  const auto in = systems::b_chatter::load_lobes_input(path);
  ASSERT_EQ(in.frfs.size(), 2u);
  EXPECT_NEAR(in.frfs[0].weight, 0.75, 1e-12);
  EXPECT_NEAR(in.frfs[1].weight, 0.25, 1e-12);
  ASSERT_TRUE(in.measured.has_value());
  const double deg = std::numbers::pi / 180.0;
  dynamics::ChatterSystem truth{{{2.26e8, 0.012, 250.0, 30.0 * deg},
                                 {1.5e9, 0.03, 900.0, 30.0 * deg},
                                 {2.13e8, 0.010, 150.0, 60.0 * deg}},
                                1e9};
  // The fit finds the two modes in the band (900 Hz lies above it): k/cos²θ within 2 %.
  ASSERT_EQ(in.modal.modes.size(), 2u);
  EXPECT_NEAR(in.modal.modes[0].natural_frequency_Hz, 150.0, 150.0 * 0.02);
  EXPECT_NEAR(in.modal.modes[0].stiffness_N_per_m / (2.13e8 / 0.25), 1.0, 0.02);
  EXPECT_NEAR(in.modal.modes[1].natural_frequency_Hz, 250.0, 250.0 * 0.02);
  EXPECT_NEAR(in.modal.modes[1].stiffness_N_per_m / (2.26e8 / 0.75), 1.0, 0.02);
  EXPECT_NEAR(in.modal.modes[1].damping_ratio / 0.012, 1.0, 0.10);
  const auto a = dynamics::frequency_domain_lobes(truth, 1000.0, 12000.0, 40, 40000);
  const auto b = dynamics::frequency_domain_lobes(in.system, 1000.0, 12000.0, 40, 40000);
  const auto c = dynamics::frequency_domain_lobes(in.modal, 1000.0, 12000.0, 40, 40000);
  dynamics::ChatterSystem in_band = truth;  // what a fit inside 40–600 Hz can find
  in_band.modes.erase(in_band.modes.begin() + 1);
  const auto a2 = dynamics::frequency_domain_lobes(in_band, 1000.0, 12000.0, 40, 40000);
  // From the fitted modes: within 1 % of the modes in the band (the 900 Hz mode's residual
  // compliance raises the truth's limit by 0.8 %; the fit leaves it out; measured −0.46 %). At
  // this file's 0.25 Hz the 150 Hz peak's half-power band holds 12 samples, under
  // kMinSamplesPerBandwidth: the residual's window is widened, and read so the limit is within
  // 1 % of the truth (read with the fine-sampling window it was 1.8 % low; the distribution
  // over noise draws is in tests/dynamics/frf_test.cpp).
  std::printf("b_frf: absolute limit from the FRF %.4f mm, fitted modes %.4f mm, modes %.4f mm "
              "(in the band %.4f mm); %.1f samples across the sharpest peak\n",
              b.critical_depth_m * 1e3, c.critical_depth_m * 1e3, a.critical_depth_m * 1e3,
              a2.critical_depth_m * 1e3, in.measured->samples_per_bandwidth);
  EXPECT_FALSE(in.measured->read_directly);
  EXPECT_NEAR(in.measured->samples_per_bandwidth, 12.0, 0.5);
  EXPECT_NEAR(c.critical_depth_m / a2.critical_depth_m, 1.0, 0.01);
  EXPECT_NEAR(b.critical_depth_m / a.critical_depth_m, 1.0, 0.01);
}

TEST(LobesFrf, MissingFileNamesTheMachineFileAndTheFrfFile) {
  try {
    std::string text = kHead;
    text += "[[frf]]\nfile = \"nowhere/tap.csv\"\n";
    (void)systems::b_chatter::parse_lobes_input(text, "/tmp/m.toml");
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("/tmp/m.toml:"), std::string::npos) << m;
    EXPECT_NE(m.find("key 'frf[0].file'"), std::string::npos) << m;
    EXPECT_NE(m.find("/tmp/nowhere/tap.csv"), std::string::npos) << m;
  }
}

// The one-line error a machine file whose [[frf]] file is FILE gives ("no error" if none).
static std::string frf_error(const std::string& file, const std::filesystem::path& dir) {
  try {
    (void)systems::b_chatter::parse_lobes_input(kHead + "[[frf]]\nfile = \"" + file + "\"\n",
                                                (dir / "m.toml").string());
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "no error";
}

// Every class a hostile [[frf]] file took off the checked path (issue 49: a FIFO blocked for
// ever, /dev/zero ate 2 GB) is one line naming the machine file, the key and the FRF file.
TEST(LobesFrf, UnreadableFilesAreRefusedBeforeAByteIsRead) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("lathectl-frf-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "dir.csv");
  const auto fifo = dir / "fifo.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  { std::ofstream(dir / "empty.csv"); }
  const std::pair<std::string, std::string> cases[] = {
      {(dir / "fifo.csv").string(), "FIFO"}, {"/dev/zero", "character device"},
      {(dir / "dir.csv").string(), "directory"}, {(dir / "none.csv").string(), "no such file"},
      {(dir / "empty.csv").string(), "empty"}};
  for (const auto& [file, why] : cases) {
    const std::string m = frf_error(file, dir);
    EXPECT_NE(m.find("m.toml:"), std::string::npos) << m;
    EXPECT_NE(m.find("key 'frf[0].file'"), std::string::npos) << m;
    EXPECT_NE(m.find(file), std::string::npos) << m;
    EXPECT_NE(m.find(why), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  std::filesystem::remove_all(dir);
}

// A fitted mode is held to a typed [[mode]]'s bounds (issue 49): an FRF whose peak lies at
// 1.5 GHz (was blamed on [speed] min_rpm) or is 1e100 m/N high (a critical depth of 1e-107 mm
// where a typed mode that soft is refused) is refused at frf[0].file, naming the FRF file.
TEST(LobesFrf, FittedModesUnderTheBoundsOfTypedModes) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("lathectl-frf-fit-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // A single mode k, ζ = 0.05 at f_n, 400 samples over 0.5..1.5 f_n: H = 1/(k(1 − r² + 2iζr)).
  const auto sdof = [&](const std::string& name, double k, double fn) {
    std::ofstream f(dir / name);
    f << "frequency_Hz,real_m_per_N,imag_m_per_N\n";
    for (int i = 0; i < 400; ++i) {
      const double r = 0.5 + i / 399.0, den = k * ((1 - r * r) * (1 - r * r) + 0.01 * r * r);
      f << r * fn << "," << (1 - r * r) / den << "," << -0.1 * r / den << "\n";
    }
    return (dir / name).string();
  };
  const std::pair<std::string, std::string> cases[] = {
      {sdof("ghz.csv", 5e7, 1.5e9), "above the 1e+06 Hz a [[mode]] may have"},
      {sdof("soft.csv", 1e-100, 500.0), "no lathe's mode is that soft"}};
  for (const auto& [file, why] : cases) {
    const std::string m = frf_error(file, dir);
    EXPECT_NE(m.find("key 'frf[0].file'"), std::string::npos) << m;
    EXPECT_NE(m.find(file), std::string::npos) << m;
    EXPECT_NE(m.find(why), std::string::npos) << m;
    EXPECT_EQ(m.find("min_rpm"), std::string::npos) << m;
  }
  // The same mode at 800 Hz and 5e7 N/m is read (the bounds refuse no lathe's mode).
  EXPECT_NO_THROW((void)systems::b_chatter::parse_lobes_input(
      kHead + "[[frf]]\nfile = \"" + sdof("ok.csv", 5e7, 800.0) + "\"\n", (dir / "m.toml").string()));
  std::filesystem::remove_all(dir);
}

// The recommendation keeps what it states: the depth is the pocket's top over the safety factor
// or the spindle's limit, the envelope at the speed is at least that depth, the power and torque
// stay within the machine's, and one grid step beyond each margin the envelope is below it.
TEST(LobesRecommend, KeepsItsOwnPromises) {
  for (const std::string machine :
       {"b_sdof", "b_two_mode", "b_part", "b_slow_high_freq", "b_frf", "b_chuck"}) {
    std::string path = LATHECTL_SOURCE_DIR;
    path += "/examples/machines/";
    path += machine;
    path += ".toml";
    const auto in = systems::b_chatter::load_lobes_input(path);
    const auto fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm,
                                                     in.max_lobes, 40000);
    const auto pockets = systems::b_chatter::recommend_pockets(fd, in);
    ASSERT_FALSE(pockets.empty()) << machine;
    const double step = (in.max_rpm - in.min_rpm) / 20000.0;
    for (const auto& p : pockets) {
      EXPECT_LE(p.depth_m, p.pocket_top_depth_m / in.recommend.safety_factor * (1 + 1e-12));
      EXPECT_GE(dynamics::envelope_depth(fd, p.speed_rpm), p.depth_m) << machine;
      EXPECT_LE(p.power_W, in.recommend.power_W * (1 + 1e-9)) << machine;
      EXPECT_LE(p.torque_Nm, in.recommend.torque_Nm * (1 + 1e-9)) << machine;
      if (!p.below_reaches_range_end) {
        EXPECT_LT(dynamics::envelope_depth(fd, p.speed_rpm - p.margin_below_rpm - step), p.depth_m);
      }
      if (!p.above_reaches_range_end) {
        EXPECT_LT(dynamics::envelope_depth(fd, p.speed_rpm + p.margin_above_rpm + step), p.depth_m);
      }
      const double v = std::numbers::pi * systems::b_chatter::recommend_diameter_m(in) *
                       p.speed_rpm / 60.0;
      EXPECT_NEAR(p.mrr_m3_per_s, v * in.recommend.feed_m * p.depth_m, 1e-15);
    }
    for (std::size_t i = 1; i < pockets.size(); ++i)
      EXPECT_GE(pockets[i - 1].mrr_m3_per_s, pockets[i].mrr_m3_per_s);
  }
}

// [part] support and steady_rest_mm: the finite-element set-ups (dynamics/beam.hpp) at the
// cutting position, the tool's modes in series; between centres without a rest the analytic
// beam as before.
TEST(LobesInput, PartSetUps) {
  std::string text = kHead;
  text += kPart;
  const auto centres = systems::b_chatter::parse_lobes_input(text, "m.toml");
  EXPECT_FALSE(centres.part->model);
  std::string chuck = text;
  chuck += "support = \"chuck\"\n";
  const auto in = systems::b_chatter::parse_lobes_input(chuck, "m.toml");
  ASSERT_TRUE(in.part->model);
  const auto fe = dynamics::beam_model_modes_at(*in.part->model, 0.1);
  ASSERT_EQ(in.system.modes.size(), fe.size());
  EXPECT_DOUBLE_EQ(in.system.modes[0].natural_frequency_Hz, fe[0].natural_frequency_Hz);
  std::string rest = text;
  rest += "support = \"chuck_tailstock\"\nsteady_rest_mm = 250\n";
  const auto r = systems::b_chatter::parse_lobes_input(rest, "m.toml");
  EXPECT_DOUBLE_EQ(r.part->supports.steady_rest_m, 0.25);
  EXPECT_EQ(r.part->supports.headstock, dynamics::BeamEnd::clamped);
  EXPECT_EQ(r.part->supports.tailstock, dynamics::BeamEnd::pinned);
  std::string bad = text;
  bad += "steady_rest_mm = 600\n";
  try {
    (void)systems::b_chatter::parse_lobes_input(bad, "m.toml");
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'part.steady_rest_mm'"), std::string::npos) << e.what();
  }
}
