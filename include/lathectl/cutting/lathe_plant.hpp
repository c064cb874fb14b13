#pragma once
// Cutting process of a lathe driven by the tool's actual path — the plant of a CNC's simulated
// machine (the LinuxCNC component lathectl_plant). Rig E follows the scenario's passes; here the
// NC program moves the tool wherever it likes, so the workpiece is a surface of revolution that
// the tool cuts down as it goes:
//
//   workpiece: radius R(z) on a grid of `cell_mm` along the part, from the scenario's blank
//              (z from its first to its last point; no material outside)
//   tool:      a round nose of radius r_n; the controlled (programmed) point (x, z) is the
//              imaginary tool tip of LinuxCNC's lathe tool orientation Q (tool table Q): the
//              nose's centre lies at (x + q_x·r_n, z + q_z·r_n), machine coordinates, with
//              (q_x, q_z) = nose_centre_offset(Q) (Q 0 or 9: the centre itself). Its lowest
//              point (x_c − r_n, z_c) cuts: edge(z') = x_c − r_n + r_n − sqrt(r_n² − (z' − z_c)²)
//              over |z' − z_c| ≤ r_n. Q 1, 2, 6 (the turning orientations) keep x_c − r_n = x:
//              a diameter is where the program puts it, and with Q 2 a face or a shoulder cut
//              toward −z at the program's z (the nose's leading point, z_c − r_n = z).
//              The insert's two straight edges leave the nose tangentially at its front and
//              back angle a (LinuxCNC's tool table I, J; AXIS's drawing: direction (sin a, cos a)
//              in machine (x, z), from the tangent point centre + r_n·(−cos a, sin a) for the
//              smaller angle, centre + r_n·(cos a, −sin a) for the larger). The tool is the
//              convex hull of the nose and the edges; the workpiece being R(z), what it cuts is
//              its lower boundary: edge(z') = min(the nose's arc, each straight edge on the lower
//              side that rises away from the nose), an edge x_t + |z' − z_t|·tan β from its
//              tangent point (x_t, z_t), for edge_length_mm along it. A face or a shoulder deeper
//              along z than the nose (2 r_n) is cut by an edge; in turning the trailing edge
//              stays above the surface the nose's lowest point left: the chip is the nose's.
//   each step: R(z') ← min(R(z'), edge(z')); the removed cross-section ΔA = Σ ΔR·dz  [mm²]
//   chip:      over the last spindle revolution (360 angle bins): A_rev = Σ ΔA, path travel
//              ℓ_rev = Σ |Δ(x, z)|;  feed per revolution s = ℓ_rev, depth t = A_rev / s
//              (longitudinal turning: s axial, t radial; facing: s radial, t axial; in steady
//              state A_rev = t·s exactly, and the first revolution builds the chip up as in rig E)
//   disturbances of the scenario: eccentric blank t + e·sin φ while the tool is on the blank
//              surface, random allowance (OU in z), hardness K(z), wear from the time in cut
//   forces:    the cutting model at (t, s, V = π·2(x + t)·n/1000, K, wear); Nc = Pz·V
//   sensor:    the scenario's force sensor (lag, noise, range) on Pz, Py or Nc; the scenario's
//              [[fault]] times count from the tool's first contact with the stock
//
// Coordinates: the scenario's stock runs along z_stock = z_origin − z_machine [mm] (the part's
// face at machine z = z_origin, the part toward −z as on a lathe); x is the radius [mm].
// Real-time: configure() allocates the grid and may throw; step() never allocates or throws.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/cutting/stock.hpp"
#include "lathectl/sensors/force_sensor.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "lathectl/sensors/faults.hpp"

namespace lathectl::cutting {

// LinuxCNC's lathe tool orientation Q (1–9; 0 and 9: the nose's centre): where the nose's centre
// lies from the programmed point, in nose radii along machine x and z — rs274ngc's
// latheorigin_x/z (interp_queue.cc) and AXIS's lathe_shapes (glcanon.py). Q 2: the tip at the
// nose's −x, −z corner (turning and facing toward the chuck, −z); Q 1: its −x, +z corner.
struct NoseOffset {
  int x = 0;
  int z = 0;
};
[[nodiscard]] constexpr NoseOffset nose_centre_offset(int q) noexcept {
  switch (q) {
    case 1: return {1, -1};
    case 2: return {1, 1};
    case 3: return {-1, 1};
    case 4: return {-1, -1};
    case 5: return {0, -1};
    case 6: return {1, 0};
    case 7: return {0, 1};
    case 8: return {-1, 0};
    default: return {0, 0};  // 0, 9: the centre
  }
}
// The orientation a scenario's tool has when it gives none: turning toward the chuck (−z), where
// the tip's x is the nose's lowest point (diameters as before the orientation was modelled).
inline constexpr int kDefaultToolOrientation = 2;
// A common insert's angles (LinuxCNC's I and J, AXIS's convention: an edge at angle a runs along
// machine (x, z) = (sin a, cos a)): a CNMG (80° rhombic) in the common 95° holder, for Q 2
// (PCLNR) I85 J5, for Q 1 (PCLNL) I95 J175 — the 80° insert set symmetrically about the
// orientation's centre line atan2(q_x, q_z). Not a default: a tool without angles (I and J both
// 0) is the nose alone, as rig E's radial plunges at a shoulder need (see straight_edges_of).
inline constexpr double kCnmgFrontAngleQ2Deg = 85.0;
inline constexpr double kCnmgBackAngleQ2Deg = 5.0;
// The length of each straight edge from its tangent point on the nose [mm]: a CNMG 12's edge.
// Beyond it the holder is taken as clear of the part.
inline constexpr double kDefaultEdgeLengthMm = 12.9;

// An insert's straight edge where it bounds the tool from below and rises away from the nose
// (else on = false), in the plant's stock coordinates (z_stock = z_origin − z_machine).
struct StraightEdge {
  bool on = false;
  int side = 0;        // +1: it runs from the nose toward stock +z, −1: toward stock −z
  double slope = 0.0;  // its rise in x per mm along z (tan β)
  double hx = 0.0;     // its tangent point's x above the nose's lowest point [mm]
  double hz = 0.0;     // its tangent point's stock z less the nose centre's [mm]
  double reach = 0.0;  // its extent along z from the tangent point [mm]
};
// The straight edges of an insert of orientation q, nose radius r_n and front and back angle
// [°], each edge_length_mm long. Both angles 0 (none given), Q 0 and 9 (the centre), and an
// included angle outside (0°, 180°): none, the nose alone. (Why no default insert: rig E plunges
// radially at a shoulder it keeps on the tool's trailing side; a CNMG's 5° edge, 12.9 mm long,
// would cut a wedge up to 12.9 mm into that shoulder — on the generated parts, tool-breakage
// and overload alarms. A real program ramps there or uses another tool.) An edge that
// bounds the tool from above, or that runs downward (an internal tool's, below the nose: the
// workpiece R(z) has no bore), cuts nothing here.
std::array<StraightEdge, 2> straight_edges_of(int q, double r_n, double front_deg,
                                              double back_deg, double edge_length_mm) noexcept;

// The cutting process of a system-E scenario: what the tool meets and what sensor 4 reads.
// Defaults are the scenario's (a random allowance correlated over 20 mm, a dynamometer that
// saturates at 10⁵ N); systems::e_adaptive::RigConfig adds the machine around it.
struct CuttingProcess {
  bool operator==(const CuttingProcess&) const = default;
  CuttingModel::Params cutting;
  StockParams stock;
  // random allowance, hardness, wear (no depth steps: the stock's passes make the depth)
  DisturbanceParams disturbances = [] {
    DisturbanceParams d;
    d.random_correlation_mm = 20.0;
    return d;
  }();
  ForceParameter force_parameter = ForceParameter::Pz;
  sensors::LaggedNoisySensor::Params force_sensor{.range = 1e5};  // N (dynamometer) or W (power)
  std::vector<sensors::SensorFault> faults;
  // The tool's orientation Q (the scenario's [tool] orientation): where its programmed point is
  // on the nose (nose_centre_offset).
  int tool_orientation = kDefaultToolOrientation;
  // The insert's front and back angle [°] (the scenario's [tool] front_angle_deg and
  // back_angle_deg, LinuxCNC's tool table I and J, AXIS's convention); both 0: none given, the
  // nose alone (straight_edges_of).
  double tool_front_angle_deg = 0.0;
  double tool_back_angle_deg = 0.0;
};

class LathePlant {
 public:
  struct Params {
    double cell_mm = 0.01;       // workpiece grid along z
    double z_origin_mm = 0.0;    // machine z of the stock's z = 0
    double nose_radius_mm = -1;  // < 0: the scenario's tool nose radius
    int orientation = -1;        // < 0: the scenario's tool orientation (tool_orientation)
    // The largest nose set_tool() may set [mm] (the scratch under the nose is sized for it at
    // configure()); below the nose radius: the nose radius.
    double max_nose_radius_mm = 0.0;
    // The insert's front and back angle [°] (LinuxCNC's I and J); not finite: the scenario's.
    double front_angle_deg = std::numeric_limits<double>::quiet_NaN();
    double back_angle_deg = std::numeric_limits<double>::quiet_NaN();
    double edge_length_mm = kDefaultEdgeLengthMm;  // each straight edge's length
  };
  struct Input {        // x or z not finite: no position (e.g. not homed) — nothing is cut
    double x_mm = 0.0;  // the programmed point (the tool tip of the orientation): machine x
    double z_mm = 0.0;  // machine z
    double rpm = 0.0;   // actual spindle speed (sign ignored)
    // > 0: a grooving or parting insert of this width [mm] cuts (io::ToolSpec::plunge()): its
    // whole width is the width of cut, the cutting law taken at t = the width and s = the feed
    // per revolution (its chip thickness); 0: the nose at its engagement t. The one copy of that
    // law (lathectl optimize's prediction, the LinuxCNC plant). The stock follows the nose (not
    // the turning insert's straight edges) and depth_mm stays the nose's chip either way.
    double insert_width_mm = 0.0;
  };
  struct Output {
    double force_measured = 0.0;   // the sensor's sample of the force parameter (N or W)
    double force_parameter = 0.0;  // its true value
    double Pz_N = 0.0;
    double Py_N = 0.0;
    double cut_power_W = 0.0;
    double depth_mm = 0.0;         // t (with runout and random allowance)
    double feed_per_rev_mm = 0.0;  // s
    double speed_m_per_min = 0.0;  // V
    double strength_factor = 1.0;
    bool in_contact = false;
    double time_in_cut_s = 0.0;
    double removed_mm3 = 0.0;      // material removed since configure(), Σ π(R_old² − R_new²)·dz
    // The depth the nose is engaged at now: the cross-section it removed over the path it
    // travelled in the last few cells of travel (held while it does not move). depth_mm is the
    // last revolution's chip and falls over a revolution when the tool leaves the material;
    // this falls within 0.03 mm of travel.
    double engaged_depth_mm = 0.0;
    bool on_blank = false;  // the nose cut the blank's own (eccentric) surface this step
    // The highest surface the nose cut this step that an earlier cut left (not the blank's own),
    // as a depth below it [mm]; 0: none, or the blank's own surface is higher. No runout deepens
    // the chip past it (a pass running off onto the blank's taper into a neck, a pass after one
    // shallower than the eccentricity): the earlier cut took the eccentric blank down to it at
    // every angle.
    double cut_surface_depth_mm = 0.0;
    // The last revolution's chip by the geometry alone, A_rev / s [mm]: depth_mm without the
    // runout and the random allowance (what a model of the blank knows).
    double chip_depth_mm = 0.0;
  };

  // Throws std::invalid_argument on a stock the grid cannot hold.
  void configure(const CuttingProcess& cfg, const Params& p);
  // Advances by dt_s. Never allocates, throws or logs.
  void step(const Input& in, double dt_s, Output& out) noexcept;
  // The workpiece alone: advances by dt_s as step() does but fills only the geometry's fields
  // of out (chip_depth_mm, feed_per_rev_mm, removed_mm3, engaged_depth_mm, on_blank), without
  // the disturbances, the forces and the sensor — what a model of the blank needs
  // (control::AdaptiveMachine's stock model). step() is cut() and then the process.
  void cut(const Input& in, double dt_s, Output& out) noexcept;
  // cut() in two halves, for a reader of the chip at fewer steps than it cuts: cut_geometry()
  // leaves out's chip_depth_mm and feed_per_rev_mm as they were; chip() fills them as cut()
  // would have at the last cut_geometry() (the bins' sums are the same additions in the same
  // order whenever they are taken: the same numbers). cut() is the one and then the other.
  void cut_geometry(const Input& in, double dt_s, Output& out) noexcept;
  void chip(Output& out) noexcept;
  // This plant's workpiece follows `leader`'s, another plant of the same blank, grid and nose
  // that is cut at the same positions, each time just before this one (rig E: its plant, and
  // the machine's stock model fed the same tool position in the same step). A cut() at the
  // position the leader's latest cut() had, the one after the cut at which both grids were last
  // equal, copies the cells the leader changed and takes its removed cross-section instead of
  // cutting them again: the same numbers, as it would have cut the same grid the same way. Any
  // other cut() — another position, the leader cut twice or not at all — cuts this plant's own
  // grid, as it does from then on (following() false). nullptr: no leader. The leader must
  // outlive the following or be unset. Not real-time: compares the grids; throws
  // std::invalid_argument when they are not equal now.
  void follow(const LathePlant* leader);
  [[nodiscard]] bool following() const noexcept { return leader_ != nullptr; }
  // The tool's orientation from now on (LinuxCNC's tool table Q of the tool in the spindle, 0–9;
  // another is taken as 0): the nose's centre moves with it, the workpiece stays. Never
  // allocates or throws.
  void set_orientation(int q) noexcept;
  // The tool in the spindle from now on (io::tool_geometry of the tool table's and tool file's
  // tool): its nose radius [mm] (clamped to (0, Params::max_nose_radius_mm]) and orientation
  // (set_orientation, which derives the straight edges again for this nose; their angles:
  // set_edges). The workpiece and the chip's revolution stay; a new radius ends
  // following (follow()) a leader, here and in this plant's followers. Never allocates or throws.
  void set_tool(double nose_radius_mm, int q) noexcept;
  // The insert's front and back angle from now on [°] (LinuxCNC's tool table I and J; both 0,
  // or an included angle max − min outside (0°, 180°): the nose alone, no straight edges).
  // Depends on the orientation and nose radius: set_orientation() and set_tool() derive the
  // edges again. Never allocates or throws.
  void set_edges(double front_deg, double back_deg) noexcept;
  // The straight edges the plant cuts with now (straight_edges_of its tool).
  [[nodiscard]] const std::array<StraightEdge, 2>& straight_edges() const noexcept {
    return edges_;
  }
  [[nodiscard]] int orientation() const noexcept { return q_; }
  // Stock z of a machine z [mm].
  [[nodiscard]] double stock_z_mm(double z_machine_mm) const noexcept {
    return p_.z_origin_mm - z_machine_mm;
  }
  // Radius of the workpiece at stock z [mm] (0 outside the stock).
  [[nodiscard]] double radius_mm(double z_stock_mm) const noexcept;
  // The largest radius of the workpiece over stock z ∈ [lo, hi] [mm] (0 where there is none):
  // where a tool path must clear what is left. Never allocates.
  [[nodiscard]] double max_radius_mm(double z_lo_mm, double z_hi_mm) const noexcept;
  // The chip a straight move would meet on the workpiece as it is now [mm], the move going from
  // the machine position (x, z) along the direction (dx, dz) (machine coordinates, any length)
  // for distance_mm:
  //   mostly along z (turning, tapers): the radial depth, the highest material within the nose's
  //     reach of the path (up to r_n beyond its end) above the lowest x the path reaches;
  //   mostly along x (plunging, facing): the axial width of the material the nose's circle
  //     meets at the path's end.
  // Both are upper bounds of the plant's t = A_rev / s along that path. Never allocates.
  [[nodiscard]] double depth_ahead_mm(double x_mm, double z_mm, double dx, double dz,
                                      double distance_mm) const noexcept;
  // The tool nose radius the plant cuts with [mm].
  [[nodiscard]] double nose_radius_mm() const noexcept { return r_nose_; }
  // Stock z of the nose's centre for the programmed machine z [mm] (the orientation's offset).
  [[nodiscard]] double nose_centre_stock_z_mm(double z_machine_mm) const noexcept {
    return stock_z_mm(z_machine_mm) - oz_;
  }
  // The nose's lowest x for the programmed machine x [mm] (x itself for Q 1, 2, 6).
  [[nodiscard]] double nose_low_x_mm(double x_mm) const noexcept { return x_mm + ox_; }

 private:
  static constexpr std::size_t kBins = 360;
  struct NoseCut {
    double removed = 0.0;  // cross-section removed this step [mm²]
    bool on_blank = false;
    double top = 0.0;           // the highest radius cut this step [mm]
    bool top_on_blank = false;  // it is the blank's own surface (else an earlier cut's)
  };
  // `edges`: with the insert's straight edges (not for a grooving or parting insert).
  NoseCut cut_under_nose(double x, double z, bool edges) noexcept;
  struct NosePass;
  static void chip_top(NoseCut& c, const NoseCut& prev, const NosePass& prev_nose,
                       std::size_t top_i, double top, bool top_on_blank) noexcept;
  void mark_high_side(double x, std::size_t j0, std::size_t n) noexcept;
  // The straight edges' cut beyond the nose's cells [i0f, i1f] (unclipped), added to c; widens
  // [lo, hi) to the cells changed.
  void cut_beyond_nose(double x, double z, bool edges, double i0f, double i1f, NoseCut& c,
                       std::size_t& lo, std::size_t& hi) noexcept;
  void edges_within_nose(double x, double z, std::size_t j0, std::size_t n,
                         double* e) const noexcept;
  // What the straight edges cut this step: the sums cut_under_nose() keeps, and [lo, hi).
  struct EdgeCut {
    double removed = 0.0;
    double mm3 = 0.0;
    double top = 0.0;
    bool on_blank = false;
    std::size_t top_i = 0;
    std::size_t lo = 0;
    std::size_t hi = 0;
  };
  void cut_along_edge(const StraightEdge& g, double xt, double zt, std::ptrdiff_t ia,
                      std::ptrdiff_t ib, EdgeCut& sums) noexcept;
  void nose_window(double x, double z, std::size_t& j0, std::size_t& j_end) const noexcept;
  void derive_edges() noexcept;
  // cut_under_nose() or, following, the leader's cut taken over; counts the cuts.
  NoseCut nose_cut(double x, double z, bool edges) noexcept;
  void edges_under_nose(double x, double z, std::size_t j0, std::size_t n,
                        double* e) const noexcept;
  [[nodiscard]] std::size_t first_centre_after(double zq, bool or_at, std::size_t lo,
                                               std::size_t hi) const noexcept;
  void spread_over_bins(double a0, double a1, double removed, double travel) noexcept;
  void revolution_sums(bool area, double& area_rev, double& travel_rev) noexcept;
  CuttingProcess cfg_{};
  Params p_{};
  double r_nose_ = 0.8;
  double r_nose_max_ = 0.8;  // what edge_ holds (Params::max_nose_radius_mm)
  int q_ = kDefaultToolOrientation;
  double ox_ = 0.0;  // the nose's lowest x less the programmed x: (q_x − 1)·r_n (0.0 for Q 2)
  double oz_ = 0.0;  // the nose centre's machine z less the programmed z: q_z·r_n
  double front_deg_ = 0.0;  // the insert's angles as given (both 0: the orientation's default)
  double back_deg_ = 0.0;
  double edge_len_ = kDefaultEdgeLengthMm;
  std::array<StraightEdge, 2> edges_{};
  bool any_edge_ = false;  // edges_[0].on || edges_[1].on
  // Per edge: its tangent point (x, stock z) at the last cut, when every cell along it
  // (edge_length_mm) was at or below it then.
  struct EdgePass {
    bool valid = false;
    double x = 0.0;
    double z = 0.0;
  };
  std::array<EdgePass, 2> last_edge_{};
  double r_top_ = 0.0;  // the blank's largest radius: no cell is higher
  // The highest cell of each block of kBlock cells, or more (cells only come down): the straight
  // edges skip the blocks below them.
  static constexpr std::size_t kBlock = 64;
  std::vector<double> block_max_;
  double z0_ = 0.0;  // stock z of the first cell
  std::vector<double> r_;
  std::vector<double> r_blank_low_;  // lowest point of the eccentric blank per cell
  double r_blank_min_ = 0.0;          // the blank's smallest mean radius
  std::vector<double> edge_;         // scratch: the nose's edge over the cells under it
  CuttingModel cut_;
  Stock stock_;
  Disturbances dist_;
  sensors::LaggedNoisySensor sensor_;
  sensors::FaultInjector faults_;
  std::array<double, kBins> bin_area_{};
  std::array<double, kBins> bin_travel_{};
  // Prefix sums of the bins from bin 0 (prefix[k] = Σ bins below k, summed in that order) and
  // the first bin changed since they were summed.
  std::array<double, kBins + 1> prefix_area_{};
  std::array<double, kBins + 1> prefix_travel_{};
  std::size_t dirty_area_ = 0;
  std::size_t dirty_travel_ = 0;
  struct NosePass {  // the last cut_under_nose() over the grid: its position and cells
    bool valid = false;
    double x = 0.0;
    double z = 0.0;
    std::size_t i0 = 0;
    std::size_t i1 = 0;
  };
  NosePass last_nose_{};
  // What chip() needs of the last cut_geometry(): whether it removed material, and the share of
  // a revolution the bins cover when they are to be scaled by it.
  struct PendingChip {
    bool removed = false;
    bool scale = false;
    double covered = 1.0;
  };
  PendingChip pending_{};
  // The latest cut_under_nose(): its position (bits compared) and the cells it may have changed.
  struct LastCut {
    double x = 0.0;
    double z = 0.0;
    std::size_t j0 = 0;
    std::size_t j_end = 0;
    NoseCut result{};
    bool edges = true;  // cut with the straight edges
  };
  LastCut last_cut_{};
  std::uint64_t cuts_ = 0;  // nose_cut() calls since configure()
  const LathePlant* leader_ = nullptr;
  std::uint64_t leader_cuts_ = 0;  // the leader's cuts_ when both grids were last equal
  double theta_ = 0.0;  // spindle angle [rev], cumulative
  std::size_t bin_ = 0;
  double last_x_ = 0.0;
  double last_z_ = 0.0;
  bool has_last_ = false;
  double t_cut_ = 0.0;
  double t_since_contact_ = -1.0;
  double removed_mm3_ = 0.0;
  double engaged_ = 0.0;
  double engaged_area_ = 0.0;
  double engaged_travel_ = 0.0;
};

}  // namespace lathectl::cutting
