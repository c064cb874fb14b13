#pragma once
// The source tree's material library, loaded once per test binary (every test reads the same
// data/materials.toml the examples use).

#include "lathectl/io/materials.hpp"

namespace lathectl::test {

inline const io::MaterialLibrary& library() {
  static const io::MaterialLibrary lib =
      io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  return lib;
}

}  // namespace lathectl::test
