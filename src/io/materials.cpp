#include "lathectl/io/materials.hpp"

#include <filesystem>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/install_paths.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {

std::string data_dir() {
  return locate_tree("LATHECTL_DATA_DIR",
                     {LATHECTL_DATA_DIR, LATHECTL_DATA_SUBDIR, LATHECTL_INSTALLED_DATA_DIR},
                     "materials.toml");
}

namespace {
cutting::PowerLaw power_law(TableReader& t, const char* key) {
  auto r = t.table(key, true);
  cutting::PowerLaw p;
  p.Cp = r->number("Cp", Range::positive());
  p.x = r->number("x", Range::closed(0, 3));
  p.y = r->number("y", Range::closed(0, 3));
  p.n = r->number("n", Range::closed(-3, 3));
  r->finish();
  return p;
}
cutting::KienzleLaw kienzle(TableReader& t, const char* key) {
  auto r = t.table(key, true);
  cutting::KienzleLaw k;
  k.k11_N_per_mm2 = r->number("k11_N_per_mm2", Range::positive());
  k.m = r->number("m", {0.0, 1.0, false, true});
  r->finish();
  return k;
}
}  // namespace

MaterialLibrary MaterialLibrary::load(const std::string& path) {
  const TomlDocument doc = TomlDocument::parse_file(path);
  TableReader root(doc.root(), path, "");
  MaterialLibrary lib;
  for (const auto& name : root.keys()) {
    auto t = root.table(name, true);
    cutting::Material m;
    m.name = name;
    m.description = t->string("description", "");
    m.strength_basis = t->choice("strength_basis", {"sigma_b_MPa", "HB"});
    m.strength = t->number("strength", Range::positive());
    m.strength_base = t->number("strength_base", Range::positive());
    m.kmp_exponent = t->number("kmp_exponent", Range::closed(0, 3));
    m.Pz = power_law(*t, "Pz");
    m.Py = power_law(*t, "Py");
    m.Px = power_law(*t, "Px");
    m.Fc = kienzle(*t, "Fc");
    m.Fp = kienzle(*t, "Fp");
    m.Ff = kienzle(*t, "Ff");
    auto ranges = t->tables("tool_life");
    if (ranges.size() > m.tool_life.size()) t->fail("tool_life", "at most 3 feed ranges");
    double prev = 0.0;
    for (auto& r : ranges) {
      cutting::ToolLifeRange lr;
      lr.feed_max_mm_per_rev = r.number("feed_max_mm_per_rev", Range::positive());
      if (!(lr.feed_max_mm_per_rev > prev)) r.fail("feed_max_mm_per_rev", "ranges must ascend");
      prev = lr.feed_max_mm_per_rev;
      lr.Cv = r.number("Cv", Range::positive());
      lr.xv = r.number("xv", Range::closed(0, 2));
      lr.yv = r.number("yv", Range::closed(0, 2));
      lr.m = r.number("m", {0.0, 2.0, true, false});
      r.finish();
      m.tool_life[static_cast<std::size_t>(m.tool_life_ranges++)] = lr;
    }
    m.kmv_exponent = t->number("kmv_exponent", Range::closed(0, 3), 0.0);
    t->finish();
    lib.materials_.push_back(std::move(m));
  }
  root.finish();
  return lib;
}

MaterialLibrary MaterialLibrary::load_default() {
  return load((std::filesystem::path(data_dir()) / "materials.toml").string());
}

const cutting::Material* MaterialLibrary::find(const std::string& name) const {
  for (const auto& m : materials_)
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<std::string> MaterialLibrary::names() const {
  std::vector<std::string> out;
  for (const auto& m : materials_) out.push_back(m.name);
  return out;
}

}  // namespace lathectl::io
