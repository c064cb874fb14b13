#include "lathectl/io/output.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <system_error>

namespace lathectl::io {

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  const auto tmp = path.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error("write failed: " + tmp);
    }
  }
  std::filesystem::rename(tmp, path);
}

std::string channels_csv(const sim::Recorder& rec) {
  std::string s;
  const auto& ch = rec.channels();
  s.reserve(rec.rows() * ch.size() * 12 + 256);
  for (std::size_t i = 0; i < ch.size(); ++i) s += (i ? "," : "") + ch[i].name;
  s += '\n';
  char buf[32];
  for (std::size_t r = 0; r < rec.rows(); ++r) {
    for (std::size_t i = 0; i < ch.size(); ++i) {
      const int n = std::snprintf(buf, sizeof buf, "%.9g", rec.column(i)[r]);
      if (i) s += ',';
      s.append(buf, static_cast<std::size_t>(n));
    }
    s += '\n';
  }
  return s;
}

}  // namespace lathectl::io
