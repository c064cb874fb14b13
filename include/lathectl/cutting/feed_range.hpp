#pragma once
// The handbook's tables by feed range (tool life: Cv, x_v, y_v, m for s up to a limit): the range
// of an ascending table that contains the feed s — the first whose feed_max_mm_per_rev ≥ s, or the
// last for larger feeds. One rule for the tool-life law (cutting_model), the seed-004 speed law
// (control/adaptive_feed_controller) and the planned mode (design/adaptive_speed).

#include <array>
#include <cstddef>

namespace lathectl::cutting {

template <class Range, std::size_t N>
[[nodiscard]] const Range& feed_range(const std::array<Range, N>& table, int ranges,
                                      double feed_mm_per_rev) noexcept {
  for (int i = 0; i < ranges; ++i)
    if (feed_mm_per_rev <= table[static_cast<std::size_t>(i)].feed_max_mm_per_rev)
      return table[static_cast<std::size_t>(i)];
  return table[static_cast<std::size_t>(ranges > 0 ? ranges - 1 : 0)];
}

}  // namespace lathectl::cutting
