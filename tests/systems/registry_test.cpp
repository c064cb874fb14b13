// Issue 43: the registry carries everything per system. Each entry's files exist where it says
// (its folder, docs page, LinuxCNC runner, configuration, display, HAL components and their man
// pages), and every system has its run and its estimate.
#include "systems/registry.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace lathectl {
namespace {

namespace fs = std::filesystem;

bool exists(const std::string& rel) {
  return fs::exists(fs::path(LATHECTL_SOURCE_DIR) / rel);
}

TEST(Registry, EveryEntryNamesFilesThatExist) {
  for (const auto& s : systems::all()) {
    const std::string id(s.id);
    EXPECT_TRUE(exists("src/systems/" + std::string(s.folder) + "/CMakeLists.txt")) << id;
    EXPECT_TRUE(exists("docs/" + std::string(s.docs))) << id << ": docs/" << s.docs;
    EXPECT_NE(s.run, nullptr) << id;
    EXPECT_NE(s.estimate, nullptr) << id;
    const auto& l = s.linuxcnc;
    if (l.runner.empty()) {
      EXPECT_TRUE(l.hal_components.empty()) << id << ": HAL components without a runner";
      continue;
    }
    EXPECT_TRUE(exists("scripts/" + std::string(l.runner))) << id << ": " << l.runner;
    EXPECT_TRUE(exists("scripts/" + std::string(l.display))) << id << ": " << l.display;
    EXPECT_TRUE(exists("hal/config/" + std::string(l.config) + ".ini")) << id << ": " << l.config;
    EXPECT_FALSE(l.hal_components.empty()) << id;
    for (const auto& c : l.hal_components) {
      EXPECT_TRUE(exists("hal/" + std::string(c.name) + ".cpp")) << id << ": " << c.name;
      EXPECT_TRUE(exists("hal/man/" + std::string(c.name) + ".9")) << id << ": " << c.name;
      EXPECT_TRUE(c.links.starts_with("lathectl_" + std::string(s.folder)))
          << id << ": " << c.name << " links " << c.links << ", not its own system's";
    }
    EXPECT_EQ(l.session.is_session == nullptr, l.session.report == nullptr) << id;
  }
}

TEST(Registry, TheLastSessionReportTakesWhatTheOthersLeave) {
  // `lathectl report` asks the entries in order; E's takes any operation log, so it is last.
  const systems::System* last = nullptr;
  for (const auto& s : systems::all())
    if (s.linuxcnc.session.is_session) last = &s;
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(last->id, "E");
}

}  // namespace
}  // namespace lathectl
