#include "lathectl/io/format.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace lathectl::io {

std::string fmt(double v, const char* format) {
  if (std::isnan(v)) return "—";
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

}  // namespace lathectl::io
