#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>

#include "lathectl/core/parameter_error.hpp"
#include "lathectl/sim/config_error.hpp"

namespace lathectl::sim {
namespace {

// The scenario key configure_as() gives what `throwing` throws.
template <class F>
std::string key_of(F&& throwing) {
  try {
    configure_as("cut", {{"step", "run.step_s"}, {"tool2_lag_mm", "cut.tool2_lag_mm"}},
                 std::forward<F>(throwing));
  } catch (const ConfigError& e) {
    return e.key();
  }
  ADD_FAILURE() << "no ConfigError";
  return "";
}

// Issue 29: the core names its own parameter; the rig maps it to the scenario key.
TEST(ConfigureAs, MapsACoreParameterToItsScenarioKey) {
  EXPECT_EQ(key_of([] { throw core::ParameterError("step", "too coarse"); }), "run.step_s");
  EXPECT_EQ(key_of([] { throw core::ParameterError("tool2_lag_mm", "too long"); }),
            "cut.tool2_lag_mm");
  // A parameter the rig does not map, or no parameter at all: the table that configures it.
  EXPECT_EQ(key_of([] { throw core::ParameterError("overlap", "out of range"); }), "cut");
  EXPECT_EQ(key_of([] { throw std::invalid_argument("bad"); }), "cut");
  // A ConfigError keeps its own key.
  EXPECT_EQ(key_of([] { throw ConfigError("run.record_interval_s", "finer"); }),
            "run.record_interval_s");
  // The message is the core's, unchanged.
  try {
    configure_as("cut", {{"step", "run.step_s"}},
                 [] { throw core::ParameterError("step", "step too coarse"); });
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "step too coarse");
  }
}

}  // namespace
}  // namespace lathectl::sim
