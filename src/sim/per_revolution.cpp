#include "lathectl/sim/per_revolution.hpp"

#include <algorithm>
#include <cmath>

namespace lathectl::sim {

std::vector<double> per_revolution_mean(std::span<const double> x, std::span<const double> rpm,
                                        double dt_s) {
  // Differences of the cumulative sum: the window may grow as well as shrink with the speed.
  std::vector<double> cum(x.size() + 1, 0.0);
  for (std::size_t i = 0; i < x.size(); ++i) cum[i + 1] = cum[i] + x[i];
  std::vector<double> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto w = static_cast<std::size_t>(
        std::max(1.0, std::round(60.0 / std::max(rpm[i], 1.0) / dt_s)));
    const std::size_t lo = i + 1 >= w ? i + 1 - w : 0;
    out[i] = (cum[i + 1] - cum[lo]) / static_cast<double>(i + 1 - lo);
  }
  return out;
}

}  // namespace lathectl::sim
