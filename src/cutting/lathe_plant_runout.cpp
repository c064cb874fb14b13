// LathePlant's eccentric blank (the geometry in lathe_plant.hpp): the chip's top where the
// nose's front meets fresh material, and the high side a pass within the runout cuts.
#include <cstddef>

#include "lathectl/cutting/lathe_plant.hpp"

namespace lathectl::cutting {

// The highest surface cut is the blank's own while its cell is still at the blank's radius
// (low + e), which the runout lifts; any other an earlier cut left, at every angle. Decided where
// the nose's front takes a cell its last position did not cover (the material as the pass found
// it); a cell that position covered is one this nose cut a step ago, and the chip's top is still
// where the front last met fresh material. Decided every step instead, a step that took no new
// cell (a step travels less than a cell: 7 µm at 0.5 mm/rev and 1700 rpm on 10 µm cells) read the
// nose's own last cut as an earlier pass's surface and clipped the runout's upper half: an
// eccentric pass's chip came out 1.4-3 % shallower than its geometry, and by how much depended on
// the simulation step (issue 47, e_stepped_life's tool life).
void LathePlant::chip_top(NoseCut& c, const NoseCut& prev, const NosePass& prev_nose,
                          std::size_t top_i, double top, bool top_on_blank) noexcept {
  if (prev_nose.valid && prev.top > 0.0 && top_i >= prev_nose.i0 && top_i <= prev_nose.i1) {
    c.on_blank = prev.on_blank;
    c.top = prev.top;
    c.top_on_blank = prev.top_on_blank;
  } else {
    c.top = top;
    c.top_on_blank = top_on_blank;
  }
}

// A pass within the runout above the blank's mean radius cuts its high side, which the grid (one
// radius a cell) cannot hold: the cells the nose's lowest point passes over are marked as no
// longer the blank's own surface, so a later pass's chip gets no runout above them (2e-9 mm lower,
// nothing counted as removed). Unmarked, a second pass read the full runout there and met a chip
// 15 % deeper than where the first pass had cut the taper before it (generated part 1157). Only
// where the nose is at or above the blank's lowest mean radius (in cut_under_nose's cell loop the
// test cost rig E 2 % of its instructions).
void LathePlant::mark_high_side(double x, std::size_t j0, std::size_t n) noexcept {
  const double ecc = cfg_.stock.eccentricity_mm;
  if (!(ecc > 0.0 && x >= r_blank_min_)) return;
  double* const r = r_.data() + j0;
  const double* const low = r_blank_low_.data() + j0;
  for (std::size_t k = 0; k < n; ++k) {
    const double ri = r[k];
    if (x >= ri && x < ri + ecc && ri > low[k] + (ecc - 1e-9)) r[k] = ri - 2e-9;
  }
}

}  // namespace lathectl::cutting
