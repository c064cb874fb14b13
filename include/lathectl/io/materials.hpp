#pragma once
// Material library (data/materials.toml): handbook and Kienzle force coefficients, tool life.

#include <string>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"

namespace lathectl::io {

// Directory of the data files: $LATHECTL_DATA_DIR, else share/lathectl of an installed program,
// else the source tree's data/ (see locate_tree in install_paths.hpp).
std::string data_dir();

class MaterialLibrary {
 public:
  static MaterialLibrary load(const std::string& path);  // throws InputError
  static MaterialLibrary load_default();                 // data_dir()/materials.toml
  [[nodiscard]] const cutting::Material* find(const std::string& name) const;
  [[nodiscard]] std::vector<std::string> names() const;

 private:
  std::vector<cutting::Material> materials_;
};

}  // namespace lathectl::io
