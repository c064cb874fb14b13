#include "lathectl/io/format.hpp"

#include <cmath>
#include <cstdio>

namespace lathectl::io {

std::string fmt(double v, const char* format) {
  if (std::isnan(v)) return "—";
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

}  // namespace lathectl::io
