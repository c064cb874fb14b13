#pragma once
// The CNC module of seed 001 (system B): vibration control by modulated feed on a twin-turret
// lathe.
//
// Staircase (ModulatedFeedGenerator): the feed rises from S_min to S_max = S_min + n_s·ΔS, one
// increment ΔS per path length Δl, then falls back the same way; one cycle is 2·n_s·Δl of path:
//   segment j = 0 .. 2n_s−1 runs at level k(j) = j (j ≤ n_s) or 2n_s − j (j > n_s), S = S_min +
//   k·ΔS
// Along the path the mean feed is (S_min + S_max)/2; in time (what productivity sees) it is the
// harmonic mean of the levels, which is lower. ΔS is a multiple of 0.1 mm/min and Δl a multiple
// of the control's resolution (the seed's constraints).
//
// Automatic module (ModulatedFeedController): from the vibration chain's a0 and ω_d (zero below
// the amplifier's dead zone), the part mass m_d and the cutting power N_c, it forms
// (S_min, ΔS, Δl, n_s) for the turret the NC block flags, by the quenching condition
//   A_P ≥ c·a0·m_d·|ω_d² − ω_m²|,   c = 1.41 by default (a parameter)
// (a forced vibration of amplitude B = A_P/(m_d·|ω_d² − ω_m²|) ≥ c·a0 quenches the self-excited
// one). The scenario key [modulation] coefficient_reading chooses c = 1.41 or c = 1/1.41, the
// two readings of the seed's formula that docs/system-b-chatter.md gives with their grounds.
// A_P, the amplitude of the force variation the
// modulation causes, follows from the force estimated from N_c: F_c = N_c/V, the force along the
// vibration F = r·F_c (r = radial_force_ratio), and F ∝ S^e (e = force_feed_exponent, 1 − m of
// the Kienzle law): A_P = F·((S_max/S_p)^e − (S_min/S_p)^e)/2.
// The levels are chosen so that the time-mean feed equals the programmed S_p (productivity kept):
// S_min is found by bisection for the given span. The staircase sums Σ_j 1/(S_min + k_j·ΔS) are
// taken term by term up to n_s = 32 and in closed form above (digamma ψ and trigamma ψ₁), so the
// re-plan costs the same at n_s = 1000 as at 32 (its cost: docs/linuxcnc.md). Inside update()
// (the simulation, and a HAL component without a planner thread) that is its worst case, once
// per replan_period_s; with a ModulationPlanner (lathectl_modfeed's `plan` function in a slower
// thread) update() only posts the request and takes the finished plan. ω_m = 2π·S_p/(2·n_s·Δl)
// (path per cycle at the programmed feed) is set to modulation_frequency_Hz, kept below the feed
// drives' bandwidth and away from ω_d/3, ω_d/2, ω_d, 2ω_d, 3ω_d (entrainment instead of
// quenching; see dynamics/van_der_pol.hpp).
//
// Beyond the seed — desynchronising the turrets (found in rig B; see docs/system-b-chatter.md,
// findings): in feed division both tools share the feed, each cutting s/2 of the surface the other
// left half a revolution earlier; their regenerative gains add, g(s/2) + g(s/2) with g ∝ h^(1−m).
// Modulating one turret makes the axial offset between them swing by
//   δ_pp = Δl · (max − min over the cycle of Σ_j (1 − S_p/S_j))   (exact for the staircase)
// and while |δ| > s/2 one tool cuts air and the other takes the whole chip: gain g(s), a factor
// 2^−(1−m) (0.71 for Kienzle m = 0.49) lower. With desync_fraction > 0 the module lengthens Δl
// (lowers ω_m) until δ_pp ≥ desync_fraction · s (s = S_p/n, the feed per revolution).
//
// Beyond the seed (what a machinist expects): the module engages after a0 > 0 for engage_time_s;
// re-plans with the largest a0 seen while the vibration persists (every replan_period_s); keeps
// the modulation to the end of the block once engaged unless release_below_dead_zone (the
// seed's literal "below the dead zone the program feeds hold", which lets chatter regrow);
// clamps the span to [s_min_fraction·S_p, s_max_fraction·S_p] and says so (ModulationLimited).
// Real-time: configure() validates and may throw; update() never allocates, throws or locks.

#include <atomic>
#include <cstdint>

#include "lathectl/control/triple_buffer.hpp"
#include "lathectl/control/types.hpp"

namespace lathectl::control {

struct ModulationPlan {
  double s_min_mm_per_min = 0.0;
  double ds_mm_per_min = 0.0;
  double dl_mm = 0.0;
  int n_s = 0;
  [[nodiscard]] bool active() const noexcept { return n_s > 0 && dl_mm > 0.0; }
  [[nodiscard]] double s_max_mm_per_min() const noexcept {
    return s_min_mm_per_min + n_s * ds_mm_per_min;
  }
  [[nodiscard]] double cycle_length_mm() const noexcept { return 2.0 * n_s * dl_mm; }
  // Time-mean feed over a cycle (harmonic mean of the staircase levels) [mm/min].
  [[nodiscard]] double time_mean_feed() const noexcept;
  // Peak-to-peak axial offset [mm] this turret builds over a cycle against one running at the
  // constant feed s_other [mm/min].
  [[nodiscard]] double offset_swing_mm(double s_other_mm_per_min) const noexcept;
};

// Executes a plan along the path. Allocation-free; the plan can be swapped at any time (the
// staircase restarts at S_min).
class ModulatedFeedGenerator {
 public:
  void start(const ModulationPlan& plan) noexcept;
  // A new plan without losing the cycle's phase (the same segment, the same fraction of it):
  // restarting at S_min on every re-plan would over-weight the low levels and drag the mean.
  void retune(const ModulationPlan& plan) noexcept;
  void stop() noexcept { plan_ = {}; }
  // Advance by the path travelled since the last call [mm]; returns the feed command [mm/min].
  double advance(double path_mm) noexcept;
  [[nodiscard]] double feed() const noexcept;
  [[nodiscard]] const ModulationPlan& plan() const noexcept { return plan_; }
  [[nodiscard]] int segment() const noexcept { return segment_; }

 private:
  ModulationPlan plan_{};
  int segment_ = 0;
  double in_segment_mm_ = 0.0;
};

enum class Turret : std::uint8_t { Right = 0, Left = 1 };
class ModulatedFeedController;

// The re-plan outside the servo thread: update() posts what it would plan for (a request) and
// takes the plan when it is ready; run() — called from a slower, lower-priority thread (HAL:
// lathectl-modfeed.plan) — plans the newest request by the controller's own plan_for(). The two
// sides exchange through TripleBuffers: no lock, no wait, no allocation on either side. Until
// run() has been called once, the controller plans inside update() as without a planner, so a
// configuration without the planner thread behaves as before. The plan then takes effect one
// planner period later than inside update(); the simulation plans inside update() (the same
// points as before, the same numbers).
class ModulationPlanner {
 public:
  struct Request {
    unsigned id = 0;
    double a0_m = 0.0, omega_d = 0.0, cut_power_W = 0.0, speed_m_per_min = 0.0,
           feed_programmed = 0.0, rpm = 0.0;
  };
  struct Result {
    unsigned id = 0;  // the request's
    double a0_m = 0.0;
    ModulationPlan plan{};
    double omega_m = 0.0, required_N = 0.0, planned_N = 0.0;
    bool limited = false;
  };
  // Planner thread. Returns true when it planned a new request.
  bool run(const ModulatedFeedController& controller) noexcept;
  [[nodiscard]] bool alive() const noexcept { return alive_.load(std::memory_order_acquire); }

 private:
  friend class ModulatedFeedController;
  TripleBuffer<Request> requests_;
  TripleBuffer<Result> results_;
  std::atomic<bool> alive_{false};
};
enum class ModulationSource : std::uint8_t { None = 0, Programmed = 1, Automatic = 2 };

class ModulatedFeedController {
 public:
  struct Params {
    double period_s = 0.001;
    double coefficient = 1.41;             // c in A_P ≥ c·a0·m_d·|ω_d² − ω_m²|
    double part_mass_kg = 3.0;             // m_d
    double radial_force_ratio = 0.3;       // force along the vibration / tangential force
    double force_feed_exponent = 0.51;     // e in F ∝ S^e
    double modulation_frequency_Hz = 2.0;  // wanted ω_m/2π
    double drive_bandwidth_Hz = 20.0;      // ω_m stays below a quarter of it
    int n_s = 5;                           // increments per ramp
    double desync_fraction = 0.0;          // > 0: δ_pp ≥ this · s (feed division); 0 = seed
    double ds_quantum_mm_per_min = 0.1;    // ΔS is a multiple of this
    double resolution_mm = 0.001;          // Δl is a multiple of this
    double s_min_fraction = 0.2;           // S_min ≥ this · S_p
    double s_max_fraction = 2.0;           // S_max ≤ this · S_p
    double engage_time_s = 0.05;
    double replan_period_s = 0.5;
    bool release_below_dead_zone = false;
    double release_time_s = 0.2;
    bool operator==(const Params&) const = default;
  };

  struct Input {
    double a0_m = 0.0;               // vibration amplitude (0 below the dead zone)
    double omega_d_rad_per_s = 0.0;  // vibration frequency (0 below the dead zone)
    double cut_power_W = 0.0;        // N_c
    double speed_m_per_min = 0.0;    // cutting speed V
    double rpm = 0.0;                // spindle speed (for the feed per revolution)
    double feed_programmed_mm_per_min[2] = {0.0, 0.0};  // S1 (right), S2 (left)
    double path_mm[2] = {0.0, 0.0};  // path travelled by each turret in the block (measured)
    bool feed_block = false;         // a cutting block is active
    ModulationSource source = ModulationSource::Automatic;
    Turret turret = Turret::Right;  // the block's turret flag
    ModulationPlan programmed{};    // the block's parameters (source Programmed)
  };

  struct Output {
    double feed_mm_per_min[2] = {0.0, 0.0};  // to feed drives 3 (right) and 6 (left)
    ModulationPlan plan{};
    bool engaged = false;
    double omega_m_rad_per_s = 0.0;
    double force_amplitude_required_N = 0.0;  // c·a0·m_d·|ω_d² − ω_m²|
    double force_amplitude_planned_N = 0.0;   // A_P of the plan
    Reason reason = Reason::None;
  };

  void configure(const Params& p);  // throws core::ParameterError naming the parameter
  // One control period: out says what to apply and why. Before configure(): an empty Output.
  void update(const Input& in, Output& out) noexcept;
  // Re-plan through `planner` (not owned; nullptr: inside update()). Set before the first update.
  void use_planner(ModulationPlanner* planner) noexcept { planner_ = planner; }
  // How the plans came since configure(): made inside update(), or taken from the planner (the
  // HAL component's plans-inline / plans-taken pins: with the planner thread running, update()
  // makes none).
  struct PlanCounts {
    std::uint32_t made_inline = 0;
    std::uint32_t taken = 0;
  };
  [[nodiscard]] PlanCounts plan_counts() const noexcept { return counts_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }

  // The plan for a measured vibration (the module's formula; pure, allocation-free). Sets
  // `limited` when the span had to be clamped.
  [[nodiscard]] ModulationPlan plan_for(double a0_m, double omega_d, double cut_power_W,
                                        double speed_m_per_min, double feed_programmed, double rpm,
                                        double& omega_m, double& required_N, double& planned_N,
                                        bool& limited) const noexcept;

 private:
  // update()'s phases (modulated_feed.cpp).
  void follow_programmed(const Input& in, int t, double step, Output& out) noexcept;
  void take_planner_answer(Output& out) noexcept;
  void request_plan(const Input& in, double s_p, Output& out) noexcept;
  Params p_{};
  bool configured_ = false;
  ModulatedFeedGenerator gen_;
  bool engaged_ = false;
  bool limited_ = false;
  double above_s_ = 0.0;
  double below_s_ = 0.0;
  double since_plan_s_ = 0.0;
  double a0_planned_ = 0.0;
  double omega_m_ = 0.0;
  double required_N_ = 0.0;
  double planned_N_ = 0.0;
  double last_path_[2] = {0.0, 0.0};
  bool was_block_ = false;
  Turret turret_ = Turret::Right;
  ModulationPlanner* planner_ = nullptr;
  unsigned next_id_ = 0;
  unsigned waiting_id_ = 0;  // the request posted to the planner (0: none)
  PlanCounts counts_{};
  void apply(const ModulationPlan& plan, double a0) noexcept;
};

}  // namespace lathectl::control
