#pragma once
// LinuxCNC's path blending (G64) at the corner between two motion segments, as its trajectory
// planner computes it: the blend arc tangent to both, the length it trims off each, its velocity
// limit. A 2-D port (the XZ plane) of LinuxCNC 2.9's src/emc/tp/blendmath.c
// (blendInit3FromLineLine / …LineArc / …ArcLine / …ArcArc, blendComputeParameters,
// blendFindPoints3, blendLineArcPostProcess, blendArcLinePostProcess, blendArcArcPostProcess)
// and tc.c (tcFindBlendTolerance, tcGetMaxTargetVel), the version Debian 12 ships (2.9.0~pre1,
// git f1270d6ed7).
//
// Why it matters: under G95 LinuxCNC plans the blend for the segments' maximum velocity
// (tcGetMaxTargetVel: a spindle-synchronised segment's target is its maxvel, 80 mm/s in the
// sample config), not for the feed, so a G64 corner without P is rounded by up to a quarter of the
// shorter segment. On examples/linuxcnc/profile_arcs.ngc's G1 Z-8 → G2 corner (28°) the arc
// starts 3.23 mm before the corner and cuts 0.30 mm inside it, at the next block's feed
// (measured in LinuxCNC: 3.25 mm, 0.30 mm). The prediction follows that path.
//
// Not ported: the parabolic and tangent alternatives
// (tpChooseBestBlend: the arc is taken whenever it can be built), consuming a short previous
// line (its geometry is the same). Which corners LinuxCNC blends at all is decided by the caller
// (predict.cpp) from what was measured.
#include "lathectl/io/canon.hpp"

namespace lathectl::optimize {

// The machine's limits the planner blends with (hal/config/lathectl-lathe.ini: [AXIS_X]/[AXIS_Z]
// MAX_ACCELERATION 500, MAX_VELOCITY 80; [DISPLAY] MAX_FEED_OVERRIDE 1; servo period 1 ms).
struct Machine {
  double accel_mm_s2 = 500.0;
  double vmax_mm_s = 80.0;
  double max_feed_scale = 1.0;
  double servo_s = 0.001;
  double kink_ratio = 0.1;  // [TRAJ] ARC_BLEND_KINK_RATIO's default
};

// A segment as the planner sees it: the share [u0, u1] of a canonical move (a piece of a split
// move is a block of its own), and the length left of it after the previous corner's trim.
struct Segment {
  const io::CanonMove* m = nullptr;
  double u0 = 0.0, u1 = 1.0;
  double left_mm = 0.0;
};

struct Corner {
  bool blended = false;
  bool reversal = false;       // the path turns back on itself: the planner stops there
  double trim_end_mm = 0.0;    // cut off the end of the first segment
  double trim_start_mm = 0.0;  // cut off the start of the second
  io::CanonMove arc;           // the blend arc, with the second segment's modal state
  double v_max_mm_s = 0.0;     // the arc's velocity limit (v_plan)
  double v_req_mm_s = 0.0;     // unsynchronised: its requested velocity
};

Corner blend_corner(const Segment& a, const Segment& b, const Machine& mc);

}  // namespace lathectl::optimize
