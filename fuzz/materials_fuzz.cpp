// libFuzzer target for the material data file parser (same contract as the scenario parser).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path =
      "/tmp/lathectl_materials_fuzz_" + std::to_string(::getpid()) + ".toml";
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    (void)lathectl::io::MaterialLibrary::load(path);
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
