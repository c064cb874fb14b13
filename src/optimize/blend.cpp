// LinuxCNC's G64 blend arc at a corner (blend.hpp: what is ported and from where).
#include "optimize/blend.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "optimize/path.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;
constexpr double kPi = std::numbers::pi;

struct V {  // a vector in the XZ plane: x (radius), z
  double x = 0.0, z = 0.0;
};
V operator+(V a, V b) { return {a.x + b.x, a.z + b.z}; }
V operator-(V a, V b) { return {a.x - b.x, a.z - b.z}; }
V operator*(double k, V a) { return {k * a.x, k * a.z}; }
double dot(V a, V b) { return a.x * b.x + a.z * b.z; }
double cross(V a, V b) { return a.x * b.z - a.z * b.x; }
double norm(V a) { return std::hypot(a.x, a.z); }
V unit(V a) {
  const double n = norm(a);
  return n > 0.0 ? (1.0 / n) * a : V{};
}
V at(const CanonMove& m, double u) {
  const auto [x, z] = point_at(m, u);
  return {x, z};
}

// The share [u0, u1] of a move as a move of its own.
CanonMove sub_move(const CanonMove& m, double u0, double u1) {
  CanonMove s = m;
  const V p0 = at(m, u0), p1 = at(m, u1);
  s.x0 = p0.x;
  s.z0 = p0.z;
  s.x1 = p1.x;
  s.z1 = p1.z;
  if (m.kind == CanonMove::Kind::Arc) {
    const double sweep = std::abs(arc_sweep(m)) * (u1 - u0);
    const int turns = static_cast<int>(std::floor(sweep / (2.0 * kPi) + 1e-9));
    s.rotation = (m.rotation > 0 ? 1 : -1) * (1 + std::max(0, turns));
  }
  return s;
}

// Unit tangent in the direction of travel at the start (u = 0) or end (u = 1).
V tangent(const CanonMove& m, bool at_end) {
  if (m.kind != CanonMove::Kind::Arc) return unit({m.x1 - m.x0, m.z1 - m.z0});
  const V c{m.xc, m.zc};
  const V r = (at_end ? V{m.x1, m.z1} : V{m.x0, m.z0}) - c;
  // point_at: x = xc + r sin a, z = zc + r cos a; d/da = (r cos a, −r sin a) = (r.z, −r.x)
  const V d = unit({r.z, -r.x});
  return arc_sweep(m) > 0.0 ? d : -1.0 * d;
}

double radius(const CanonMove& m) { return std::hypot(m.x0 - m.xc, m.z0 - m.zc); }

// tc->maxvel: the move's velocity limit from the axes' (and, for an arc, its normal
// acceleration, BLEND_ACC_RATIO_NORMAL = √(1 − 0.5²)).
double max_vel(const CanonMove& m, const Machine& mc) {
  if (m.kind != CanonMove::Kind::Arc) {
    const V u = unit({m.x1 - m.x0, m.z1 - m.z0});
    const double k = std::max(std::abs(u.x), std::abs(u.z));
    return k > 0.0 ? mc.vmax_mm_s / k : mc.vmax_mm_s;
  }
  return std::min(mc.vmax_mm_s, std::sqrt(mc.accel_mm_s2 * std::sqrt(0.75) * radius(m)));
}

bool synchronised(const CanonMove& m) { return m.kind != CanonMove::Kind::Traverse && m.per_rev; }

// tcGetMaxTargetVel: a spindle-synchronised (G95) move's is its maxvel whatever the feed; an
// unsynchronised one's is its requested velocity times the largest feed override.
double target_vel(const CanonMove& m, double scale, const Machine& mc) {
  const double vmax = max_vel(m, mc);
  if (synchronised(m)) return vmax;
  const double req = m.kind == CanonMove::Kind::Traverse ? vmax : m.feed / 60.0;
  return std::min(req * scale, vmax);
}

// tcFindBlendTolerance: G64 P, or a quarter of the segment when none was given.
double blend_tolerance(const CanonMove& a, double len_a, const CanonMove& b, double len_b) {
  const double t1 = a.blend_tol_mm > 0.0 ? a.blend_tol_mm : 0.25 * len_a;
  const double t2 = b.blend_tol_mm > 0.0 ? b.blend_tol_mm : 0.25 * len_b;
  return std::min({t1, t2, 0.25 * len_a, 0.25 * len_b});
}

struct Params {
  double theta = 0.0, phi = 0.0, L1 = 0.0, L2 = 0.0, tolerance = 0.0;
  double v_goal = 0.0, v_req = 0.0, a_max = 0.0, a_n = 0.0;
  double v_plan = 0.0, R_plan = 0.0, d_plan = 0.0;
};

// blendComputeParameters (2.9, without S-curve).
bool compute(Params& p) {
  const double h_tol = p.tolerance / (1.0 - std::sin(p.theta));
  const double d_tol = std::cos(p.theta) * h_tol;
  const double d_geom = std::min({p.L1, p.L2, d_tol});
  const double R_geom = std::tan(p.theta) * d_geom;
  const double v_normal = std::sqrt(p.a_n * R_geom);
  p.v_plan = std::min(v_normal, p.v_goal);
  const double a_par = 0.5 * p.a_max;
  const double v_triangle = std::sqrt(2.0 * a_par * d_geom);
  const double t_blend = std::min(v_triangle, p.v_plan) / a_par;
  const double s_blend = t_blend * p.v_plan;
  const double R_blend = std::min(s_blend / p.phi, R_geom);
  p.R_plan = std::max(p.v_plan * p.v_plan / p.a_n, R_blend);
  p.d_plan = p.R_plan / std::tan(p.theta);
  return p.R_plan >= 1e-12 && p.R_plan * p.phi >= 1e-6 && std::isfinite(p.d_plan);
}

// The blend circle of radius R tangent to a line (through P, direction u, the circle on the side
// n) and to a circle (centre C, radius r; outside it when d = R + r, inside when d = r − R):
// the distance along the line from P to the tangent point (blend*PostProcess's quadratic; its
// two roots for ±u are each other's negatives, so the smaller |root| serves either way).
bool tangent_to_line_and_circle(V P, V u, V n, V C, double d, double R, double& d_L) {
  const V rc = C - P;
  const double cu = dot(rc, u), cn = dot(rc, n);
  const double B = 2.0 * cu;
  const double Cq = cu * cu - d * d + (R - cn) * (R - cn);
  const double disc = B * B - 4.0 * Cq;
  if (disc < 0.0) return false;
  const double s = std::sqrt(disc);
  d_L = std::min(std::abs((-B + s) / 2.0), std::abs((-B - s) / 2.0));
  return true;
}

// blendInit3From{Line,}Arc / ArcLine / ArcArc, an arc's side of the corner: the angle the blend
// may take of it (`share`: two thirds of what is left of the first arc, a third of the second;
// at most the corner's half angle when the arc is convex), the corner angle that leaves
// (`theta`, lowered), and the length along the arc it offers.
double arc_side(bool convex, double share, double theta_tan, double r, double& theta) {
  const double phi_max = std::min(share, convex ? theta_tan : kPi / 2.0);
  if (convex) theta = std::min(theta, theta_tan - phi_max / 4.0);
  return convex ? std::sin(phi_max / 4.0) * r : phi_max * r;
}

// findTrimAngle: the angle at the arc's centre C between the corner P and the blend's centre.
double trim_angle(V P, V C, V centre) {
  return std::acos(std::clamp(dot(unit(P - C), unit(centre - C)), -1.0, 1.0));
}

// One corner between two segments, as blend_corner reads it.
struct CornerGeometry {
  CanonMove a, b;
  double len_a = 0.0, len_b = 0.0;
  bool arc_a = false, arc_b = false;
  V P, t1, t2;             // the corner, the tangents at a's end and b's start
  double theta_tan = 0.0;  // half the angle between the two directions
  bool convex = false;     // the first arc's convexity (or the only arc's)
  bool convex2 = false;    // arc to arc: the second's
};

// tpSetupTangent: a small kink is taken as tangent (no blend arc).
bool kink_is_tangent(const CornerGeometry& g, const Params& p, const Machine& mc) {
  const double v_max = std::min(target_vel(g.a, mc.max_feed_scale, mc),
                                target_vel(g.b, mc.max_feed_scale, mc));
  const double a_inst = v_max / mc.servo_s + p.a_max;
  const V diff = a_inst * (g.t2 - g.t1);
  double scale = std::max(std::abs(diff.x), std::abs(diff.z)) / p.a_max;
  if (g.arc_a || g.arc_b) scale /= 0.5;  // BLEND_ACC_RATIO_TANGENTIAL
  return scale < mc.kink_ratio;
}

// The lengths of each segment the blend may use (blendInit3From*); false: no blend.
bool blend_lengths(CornerGeometry& g, double left_mm, Params& p) {
  const CanonMove &a = g.a, &b = g.b;
  const double left_a = std::min(left_mm, g.len_a);
  // An arc trimmed at its start by the previous corner's blend keeps only the rest of its sweep
  // (tcSetCircleXYZ): what the next corner's limits see.
  const double sweep_a = g.arc_a ? left_a / radius(a) : 0.0;
  if (!g.arc_a && !g.arc_b) {  // blendInit3FromLineLine (BLEND_DIST_FRACTION 0.5)
    p.L1 = std::min(left_a, 0.5 * g.len_a);
    p.L2 = 0.5 * g.len_b;
  } else if (g.arc_a && g.arc_b) {  // blendInit3FromArcArc
    const V C1{a.xc, a.zc}, C2{b.xc, b.zc};
    g.convex = dot(g.P - C1, g.t2) < 0.0;
    g.convex2 = !(dot(g.P - C2, g.t1) < 0.0);
    p.L1 = arc_side(g.convex, sweep_a * 2.0 / 3.0, g.theta_tan, radius(a), p.theta);
    p.L2 = arc_side(g.convex2, std::abs(arc_sweep(b)) / 3.0, g.theta_tan, radius(b), p.theta);
    if (p.theta < kPi / 12.0) return false;
  } else if (g.arc_b) {  // blendInit3FromLineArc
    const V C2{b.xc, b.zc};
    g.convex = !(dot(g.P - C2, g.t1) < 0.0);  // arcConvexTest(..., reverse_dir = true)
    p.L1 = std::min(left_a, 0.5 * g.len_a);
    p.L2 = arc_side(g.convex, std::abs(arc_sweep(b)) / 3.0, g.theta_tan, radius(b), p.theta);
  } else {  // blendInit3FromArcLine
    const V C1{a.xc, a.zc};
    g.convex = dot(g.P - C1, g.t2) < 0.0;  // arcConvexTest(..., reverse_dir = false)
    p.L1 = arc_side(g.convex, sweep_a * 2.0 / 3.0, g.theta_tan, radius(a), p.theta);
    p.L2 = 0.5 * g.len_b;
  }
  return true;
}

// blendParamKinematics: the requested and goal speeds through the blend.
void blend_kinematics(const CornerGeometry& g, const Machine& mc, Params& p) {
  const CanonMove &a = g.a, &b = g.b;
  p.v_req = std::max(target_vel(a, 1.0, mc), target_vel(b, 1.0, mc));
  p.v_goal =
      std::max(target_vel(a, mc.max_feed_scale, mc), target_vel(b, mc.max_feed_scale, mc));
  double v_max = mc.vmax_mm_s;  // the planar limit: min(v_x, v_z)
  if (!g.arc_a && !g.arc_b) {   // the "altitude" limit of two lines
    const double phi_eff = std::min(p.phi, kPi * 0.49);
    const double m1 = max_vel(a, mc), m2 = max_vel(b, mc);
    const double v1 = std::min(m1, m2 / std::cos(phi_eff));
    const double v2 = std::min(m2, m1 / std::cos(phi_eff));
    const double base = norm(v2 * g.t2 - v1 * g.t1);
    if (base > 0.0) v_max = std::max(v_max, v1 * v2 * std::sin(p.phi) / base);
  }
  p.v_goal = std::min(p.v_goal, v_max);
}

// The arc's centre and where it meets each segment (blendFindPoints3, blend*PostProcess);
// false: no blend.
bool blend_centre(const CornerGeometry& g, const Params& p, V& centre, Corner& out) {
  const CanonMove &a = g.a, &b = g.b;
  const V P = g.P, t1 = g.t1, t2 = g.t2;
  const V bis = unit(t2 - t1);  // towards the inside of the corner
  if (!g.arc_a && !g.arc_b) {   // blendFindPoints3
    centre = P + (p.R_plan / std::sin(p.theta)) * bis;
    out.trim_end_mm = out.trim_start_mm = p.d_plan;
  } else if (g.arc_a && g.arc_b) {  // blendArcArcPostProcess: the centre d1, d2 from C1, C2
    const V C1{a.xc, a.zc}, C2{b.xc, b.zc};
    const double d1 = (g.convex ? -p.R_plan : p.R_plan) + radius(a);
    const double d2 = (g.convex2 ? -p.R_plan : p.R_plan) + radius(b);
    const double c2x = norm(C2 - C1);
    if (!(c2x > 0.0)) return false;
    const double Cx = (-d1 * d1 + d2 * d2 - c2x * c2x) / (-2.0 * c2x);
    const double Cy2 = d1 * d1 - Cx * Cx;
    if (!(Cy2 >= 0.0)) return false;
    const V uc = unit(C2 - C1);
    V nc{-uc.z, uc.x};
    if (dot(bis, nc) < 0.0) nc = -1.0 * nc;
    const V c1 = C1 + Cx * uc;
    const V plus = c1 + std::sqrt(Cy2) * nc, minus = c1 - std::sqrt(Cy2) * nc;
    centre = norm(minus - P) < norm(plus - P) ? minus : plus;  // the solution nearer P
    if (norm(centre - P) - p.R_plan > p.tolerance) return false;
    out.trim_end_mm = trim_angle(P, C1, centre) * radius(a);
    out.trim_start_mm = trim_angle(P, C2, centre) * radius(b);
  } else if (g.arc_b) {  // blendLineArcPostProcess
    const V n1 = cross(t1, t2) > 0.0 ? V{-t1.z, t1.x} : V{t1.z, -t1.x};
    const V C2{b.xc, b.zc};
    const double d2 = (g.convex ? -p.R_plan : p.R_plan) + radius(b);
    double d_L = 0.0;
    if (!tangent_to_line_and_circle(P, t1, n1, C2, d2, p.R_plan, d_L)) return false;
    centre = P - d_L * t1 + p.R_plan * n1;
    if (norm(centre - P) - p.R_plan > p.tolerance) return false;
    out.trim_end_mm = d_L;
    out.trim_start_mm = trim_angle(P, C2, centre) * radius(b);
  } else {  // blendArcLinePostProcess
    const V n2 = cross(t1, t2) > 0.0 ? V{-t2.z, t2.x} : V{t2.z, -t2.x};
    const V C1{a.xc, a.zc};
    const double d1 = (g.convex ? -p.R_plan : p.R_plan) + radius(a);
    double d_L = 0.0;
    if (!tangent_to_line_and_circle(P, t2, n2, C1, d1, p.R_plan, d_L)) return false;
    centre = P + d_L * t2 + p.R_plan * n2;
    if (norm(centre - P) - p.R_plan > p.tolerance) return false;
    out.trim_start_mm = d_L;
    out.trim_end_mm = trim_angle(P, C1, centre) * radius(a);
  }
  return true;
}

}  // namespace

Corner blend_corner(const Segment& sa, const Segment& sb, const Machine& mc) {
  Corner out;
  CornerGeometry g;
  g.a = sub_move(*sa.m, sa.u0, sa.u1);
  g.b = sub_move(*sb.m, sb.u0, sb.u1);
  g.len_a = move_length(g.a);
  g.len_b = move_length(g.b);
  if (!(g.len_a > 1e-9) || !(g.len_b > 1e-9)) return out;
  g.arc_a = g.a.kind == CanonMove::Kind::Arc;
  g.arc_b = g.b.kind == CanonMove::Kind::Arc;
  g.P = V{g.a.x1, g.a.z1};
  g.t1 = tangent(g.a, true);
  g.t2 = tangent(g.b, false);
  g.theta_tan = std::acos(std::clamp(-dot(g.t1, g.t2), -1.0, 1.0)) / 2.0;
  out.reversal = g.theta_tan < 1e-6;
  if (kPi / 2.0 - g.theta_tan < 1e-6 || out.reversal) return out;  // tangent, or a reversal

  Params p;
  p.a_max = mc.accel_mm_s2;  // calculateInscribedDiameter in the XZ plane: min(a_x, a_z)
  p.a_n = p.a_max * std::sqrt(0.75);
  if (kink_is_tangent(g, p, mc)) return out;
  p.theta = g.theta_tan;
  p.tolerance = blend_tolerance(g.a, g.len_a, g.b, g.len_b);
  if (!blend_lengths(g, sa.left_mm, p)) return out;
  p.phi = kPi - 2.0 * p.theta;
  blend_kinematics(g, mc, p);
  if (!compute(p)) return out;
  V centre;
  if (!blend_centre(g, p, centre, out)) return out;
  if (!(out.trim_end_mm < g.len_a) || !(out.trim_start_mm < g.len_b)) return out;
  const double ua = 1.0 - out.trim_end_mm / g.len_a, ub = out.trim_start_mm / g.len_b;
  const V q1 = at(g.a, ua), q2 = at(g.b, ub);
  out.arc = *sb.m;  // the planner's state when the second segment was queued (tcSetupState)
  out.arc.kind = CanonMove::Kind::Arc;
  out.arc.x0 = q1.x;
  out.arc.z0 = q1.z;
  out.arc.x1 = q2.x;
  out.arc.z1 = q2.z;
  out.arc.xc = centre.x;
  out.arc.zc = centre.z;
  // Counter-clockwise in (z, x) (path.hpp) is a turn to the left seen with x up and z right.
  out.arc.rotation = cross(g.t1, g.t2) < 0.0 ? 1 : -1;
  out.v_max_mm_s = p.v_plan;
  out.v_req_mm_s = p.v_req;
  out.blended = true;
  return out;
}

}  // namespace lathectl::optimize
