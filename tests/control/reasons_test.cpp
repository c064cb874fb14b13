// The reason table (control/types.hpp) lists every Reason exactly once, with a unique name and a
// distinct operation-log bit, and reason_name()/is_alarm()/reason_bit() read it.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>

#include "lathectl/control/types.hpp"

namespace lathectl::control {
namespace {

// True for the enumerators of Reason. No default: -Wswitch (an error with -Werror) names an
// enumerator added to Reason and missing here, so this list cannot fall behind the enum.
bool enumerator(Reason r) {
  switch (r) {
    case Reason::None:
    case Reason::OutputHigh:
    case Reason::OutputLow:
    case Reason::RateLimited:
    case Reason::SensorNotFinite:
    case Reason::SensorOutOfRange:
    case Reason::SensorStuck:
    case Reason::SensorSuspect:
    case Reason::Overload:
    case Reason::ToolBreakage:
    case Reason::ToolDataChanged:
    case Reason::AirCut:
    case Reason::Engaged:
    case Reason::NotInFeedBlock:
    case Reason::StockAhead:
    case Reason::SpindleSpeedLimit:
    case Reason::SpindlePowerLimit:
    case Reason::ModulationEngaged:
    case Reason::ModulationReleased:
    case Reason::ModulationLimited:
    case Reason::ModulationProgrammed:
    case Reason::ModulationNoForce:
    case Reason::GaugeBackstop:
    case Reason::GaugeStep:
    case Reason::GaugeSize:
    case Reason::GaugeSignalLost:
    case Reason::GaugeUnreachable:
    case Reason::SlideOff:
    case Reason::ModulationNoIdle:
    case Reason::GaugeNoRoundSurface:
    case Reason::PowerAccelerationUnknown:
      return true;
  }
  return false;
}

TEST(ReasonTable, EveryEnumeratorListedOnceAndNothingElse) {
  int enumerators = 0;
  for (std::uint32_t v = 0; v <= UINT16_MAX; ++v) {
    const auto r = static_cast<Reason>(v);
    int listed = 0;
    for (const auto& e : kReasons) listed += e.code == r ? 1 : 0;
    if (enumerator(r)) {
      ++enumerators;
      EXPECT_EQ(listed, 1) << "code " << v;
      EXPECT_EQ(kReasons[reason_index(r)].code, r) << "code " << v;
    } else {
      EXPECT_EQ(listed, 0) << "code " << v << " is in the table but not in enum Reason";
      EXPECT_EQ(reason_index(r), -1);
      EXPECT_EQ(reason_bit(r), 0u);
      EXPECT_EQ(reason_name(r), "unknown");
      EXPECT_FALSE(is_alarm(r));
    }
  }
  EXPECT_EQ(enumerators, kReasonCount);
}

TEST(ReasonTable, NamesUniqueBitsDistinctEveryRowFilled) {
  std::set<std::string> names;
  std::uint32_t bits = 0;
  for (int i = 0; i < kReasonCount; ++i) {
    const auto& e = kReasons[i];
    EXPECT_TRUE(names.insert(std::string(e.name)).second) << e.name << " twice";
    EXPECT_EQ(reason_index(e.code), i);
    EXPECT_EQ(reason_bit(e.code), std::uint32_t{1} << i);
    EXPECT_EQ(bits & reason_bit(e.code), 0u) << e.name << " shares a bit";
    bits |= reason_bit(e.code);
    EXPECT_EQ(reason_name(e.code), e.name);
    EXPECT_EQ(is_alarm(e.code), e.alarm);
    EXPECT_FALSE(e.meaning.empty()) << e.name;
    EXPECT_FALSE(e.systems.empty()) << e.name;
    EXPECT_EQ(e.meaning.back(), '.') << e.name << ": one sentence";
  }
  // The codes ≥ 31 that a 1 << code mask lost reach the log.
  for (const Reason r : {Reason::Engaged, Reason::NotInFeedBlock, Reason::SpindleSpeedLimit,
                         Reason::SpindlePowerLimit, Reason::GaugeBackstop})
    EXPECT_NE(reason_bit(r), 0u) << reason_name(r);
}

TEST(ReasonTable, AlarmsAreTheLatchingFaults) {
  for (const Reason r :
       {Reason::SensorNotFinite, Reason::SensorOutOfRange, Reason::SensorStuck, Reason::Overload,
        Reason::ToolBreakage, Reason::ToolDataChanged, Reason::GaugeBackstop})
    EXPECT_TRUE(is_alarm(r)) << reason_name(r);
  for (const Reason r : {Reason::None, Reason::SensorSuspect, Reason::AirCut, Reason::Engaged,
                         Reason::SpindlePowerLimit, Reason::ModulationLimited})
    EXPECT_FALSE(is_alarm(r)) << reason_name(r);
}

}  // namespace
}  // namespace lathectl::control
