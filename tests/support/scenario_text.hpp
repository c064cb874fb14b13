#pragma once
// An example scenario's text, and that text with one passage replaced: for tests that parse an
// edited example (the other settings tests have local copies of the same two functions).

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace lathectl::test {

inline std::string example_text(const std::string& name) {
  std::ifstream in(LATHECTL_SOURCE_DIR "/examples/scenarios/" + name + ".toml", std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `text` with the first occurrence of `from` replaced by `to` (a test failure if absent).
inline std::string edited(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

}  // namespace lathectl::test
