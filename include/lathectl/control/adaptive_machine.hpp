#pragma once
// System E's machine side: everything a lathe runs for adaptive control, in one object that the
// simulated rig (`lathectl run`), the LinuxCNC component lathectl_adaptive and the optimiser's
// prediction all run. The component is a map from HAL pins to Input and Output; the rig fills
// Input from its simulated machine. Around the control law (AdaptiveFeedController) it holds:
//
//   settings     per operation from the NC program (motion's analog outputs: limit, feed
//                bounds, mode, operation number; 0 = not set), else the tool's row of the tool
//                table, else the scenario's; a bad value is never used (the last good settings
//                stay, the feed holds, bad_code/bad_line/bad_value say what and where)
//   load         sensor 4 (force), or with the power sensor the cutting power at the spindle:
//                  P_cut = η·(P_drive − P_idle(n)) − J·ω·dω/dt   (braking: (P_drive − P_idle)/η)
//                P_idle learned outside feed moves at steady speed (IdleTare; the scenario's
//                law until a bin near the speed is learned), and the power that accelerates
//                the spindle's inertia J taken off (ω from the measured speed, its derivative
//                lagged as the power meter lags). Without the last term a speed change — the
//                speed law's, or the spindle's run-up after a pass change — reads as cutting
//                power of either sign.
//   contact      ContactDetector on the load in feed moves (the controller's rule, run in
//                every mode: teach-in and the log need it when the controller does not regulate)
//   load_rev     the load's per-revolution mean (PerRevolutionMean: the controller's own
//                definition), what overload levels, the panel and the operation log see
//   overload     warn and hold levels, percentages of the reference (taught, else the limit)
//   teach-in     the mean steady load of a teach cut (TeachIn), stored per (tool, operation)
//   op record    one record per program line (or tool) with feed moves: mean and peak of
//                load_rev, feed factor, times, every reason code seen (reason_mask, a bit per
//                position in the reason table), the first alarm
//   feed-forward with the stock model: the depth the tool's path meets ahead (a step, a collar,
//                the blank coming into reach: LathePlant::depth_ahead_mm, over the nose and
//                feed_forward_revs revolutions at the highest feed) rising above what it cuts
//                now gives the controller a ceiling, the feed that depth takes at the limit by
//                the handbook's law times κ, the specific force the cut has shown (measured
//                per-revolution load over the law's at the geometric chip, learned in steady
//                cuts: hardness and wear). The regulator corrects what the model does not know.
//   breakage     path-aware (PathBreakage on the stock model's predicted depth) when the stock
//                model is on; else the controller's own collapse detector
//   tool data    the tool's number, offsets or table row changing inside a feed move: alarm 22
//   feed         the program's feed per revolution (G95: the F word, recovered from feed-upm on
//                arcs; G94: velocity/n), the controller's feed over it, split into motion's feed
//                scale and adaptive-feed with the operator's knob (split_feed_override)
//   spindle      the speed law's speed while the program runs the spindle, else the program's
//
// It runs every servo period; the control law every `period_s` (a whole number of servo
// periods, else period_error and a held feed). Every latching detector counts the period as
// measured (Input::elapsed_s), not the nominal one.
// Real-time: configure() allocates and may throw; update() never allocates, throws, locks or
// logs.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/control/contact.hpp"
#include "lathectl/control/operation_control.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/drives/spindle_drive.hpp"

namespace lathectl::control {

class AdaptiveMachine {
 public:
  static constexpr std::size_t kMaxTools = 64;
  static constexpr std::size_t kMaxTaught = 256;

  struct Taught {
    bool operator==(const Taught&) const = default;
    int tool = -1;
    int operation = 0;
    double reference = 0.0;  // the taught mean load, in the load's unit
  };

  struct Params {
    bool operator==(const Params&) const = default;
    AdaptiveFeedController::Params controller;
    // What sensor 4 measures (the cutting power the speed law limits is computed from it).
    cutting::ForceParameter parameter = cutting::ForceParameter::Pz;
    // The load is the spindle drive's power (Input::spindle_power_W), not Input::force.
    bool power_sensor = false;
    // The spindle: its idle law (the prior until the tare has learned), efficiency η,
    // inertia J, speed range.
    drives::SpindleDrive::Params spindle;
    // The drive's power reading lags the power it draws by this time constant [s]: the
    // acceleration power J·ω·dω/dt is lagged alike before it is taken off.
    double power_lag_s = 0.0;
    // The spindle's inertia learned from the drive's own power in air (rapids, dwells, the idle
    // sweep): every speed change there draws η⁻¹·J·ω·dω/dt above the idle power (returns η·of it
    // braking), so J is the least-squares slope of that power on ω·dω/dt. spindle.inertia_kg_m2
    // is the prior until learn_inertia_min_s of clear acceleration (|dω/dt| above 20 rad/s²)
    // has been seen.
    bool learn_inertia = false;
    double learn_inertia_min_s = 0.3;
    OperationRating rating;
    std::vector<ToolLimits> tools;  // at most kMaxTools
    std::vector<Taught> taught;     // at most kMaxTaught; more are taught at run time up to it
    // The stock model for the path-aware breakage detector: the scenario's blank cut down by
    // the tool's path (machine z of the stock's face: z_origin_mm). It replaces the controller's
    // collapse detector (its spike detector stays).
    bool stock_model = false;
    // Feed-forward from the stock model (only with it): look ahead over the nose and this many
    // revolutions at the highest feed; act on a rise of the depth ahead above (1 + rise)·depth
    // now + 0.02 mm; κ's time constant [s] (in cut).
    bool feed_forward = true;
    double feed_forward_revs = 1.5;
    double feed_forward_rise = 0.1;
    double specific_force_time_s = 0.5;
    // The tool-life speed law (with the stock model and the depth-corrected law): the depth from
    // the stock model's chip, not from the force, and V_opt times K_mv(ĥ)/K_mv(1), the hardness
    // ĥ = κ^(1/kmp) that the cut's specific force κ shows (K_mp = h^kmp, the handbook's).
    bool life_law = false;
    cutting::CuttingProcess process;
    double z_origin_mm = 0.0;
    // The feed scale's resolution: halui.feed-override.scale with direct-value (the sample
    // config), counts × scale.
    double override_step = 0.001;
    // The feed scale motion reports disagreeing with the one commanded: halui sends a value only
    // when its counts change, so a value another client set since (AXIS's slider sends its own
    // when it redraws) would stay. After rescale_after_s (well beyond halui's measured
    // 0.1-0.2 s) the counts step one down for rescale_for_s (over two of halui's 20 ms loops),
    // and halui sends the commanded value again.
    double rescale_after_s = 0.5;
    double rescale_for_s = 0.05;
  };

  using Motion = control::Motion;  // motion.motion-type (types.hpp)

  struct Input {
    double nominal_period_s = 0.001;  // the thread's period
    double elapsed_s = 0.0;           // measured since the last call; 0: nominal
    bool enable = true;
    bool reset = false;  // rising edge: clears the latched alarms
    double force = 0.0;  // sensor 4 (N, or W for the power parameter)
    double spindle_power_W = 0.0;  // the spindle drive's electrical power (power sensor)
    double rpm = 0.0;              // measured spindle speed (sign ignored)
    double rpm_programmed = 0.0;   // the program's S (signed: the direction)
    double current_vel_mm_s = 0.0;  // the path's measured velocity (sensor 12)
    // motion.requested-vel: under G95 the F word [mm/rev] on straight moves (on arcs the arc's
    // velocity limit); under G94 [mm/s]. Without the feed scale.
    double requested_vel = 0.0;
    double feed_upm = 0.0;  // motion.feed-upm: the move's F times motion's net feed scale
    std::int32_t motion_type = 0;  // Motion
    bool per_rev = true;           // G95
    double x_mm = 0.0;             // tool radius
    double z_mm = 0.0;
    bool homed = true;  // positions mean something (motion.is-all-homed)
    double cutting_speed_m_per_min = 0.0;  // a measured V; 0: π·2x·n
    // The program's per-operation settings (M68 E0..E4; 0 = not set).
    double limit_cmd = 0.0, feed_min_cmd = 0.0, feed_max_cmd = 0.0, mode_cmd = 0.0,
           operation_cmd = 0.0;
    std::int32_t tool_number = 0;
    std::int32_t program_line = -1;
    double tool_diameter = 0.0, tool_offset_x = 0.0, tool_offset_z = 0.0;
    double knob = 1.0;            // the operator's feed override
    double max_override = 1.0;    // [DISPLAY]MAX_FEED_OVERRIDE
    double scale_in_motion = 0.0;  // the feed scale motion reports (0: not wired)
  };

  // One operation's record, published when the operation ends (seq counts them).
  struct OperationRecord {
    std::int32_t seq = 0, line = 0, tool = 0, operation = 0, mode = 0;
    double limit = 0.0, load_mean = 0.0, load_peak = 0.0, feed_min = 1.0, feed_mean = 1.0,
           time_in_cut_s = 0.0, time_s = 0.0;
    std::uint32_t reasons = 0;  // reason_bit() of every reason seen in cut
    std::int32_t alarm = 0;     // the first alarm's reason code
  };
  struct TeachRecord {
    std::int32_t seq = 0, tool = 0, operation = 0;
    double reference = 0.0;
  };

  // The caller keeps its Output between calls, as HAL pins keep their values: update() writes
  // what changed.
  struct Output {
    double adaptive_feed = 1.0;     // motion.adaptive-feed, [0, 1]
    double feed_override = 1.0;     // motion's feed scale to command
    std::int32_t feed_override_counts = 1000;
    double feed_factor = 1.0;       // the net override of the program's feed
    double spindle_speed_out = 0.0;
    double spindle_override = 1.0;
    bool feed_hold = false;
    bool alarm = false;
    Reason reason = Reason::None;
    Reason alarm_reason = Reason::None;
    double feed_per_rev_mm = 0.0;   // the controller's
    double speed_cmd_m_per_min = 0.0;
    double speed_opt_m_per_min = 0.0;
    double depth_estimate_mm = 0.0;
    double cut_power_W = 0.0;
    bool in_cut = false;  // the controller's regulator is in the cut
    bool contact = false;  // the tool is in the material (every mode)
    bool period_error = false;
    double load = 0.0;  // what the controller sees (N, or W with the power sensor)
    double limit = 0.0, feed_min = 0.0, feed_max = 0.0;
    bool adaptive_on = true, teaching = false;
    double idle_power_W = 0.0;
    bool tare_ready = false;
    std::array<double, 3> idle_law{};  // p0 [W], p1 [W/rpm], p2 [W/rpm²]
    double acceleration_power_W = 0.0;  // J·ω·dω/dt, lagged as the meter
    double inertia_kg_m2 = 0.0;         // J in use (learned, else the given one)
    bool inertia_learned = false;
    bool bad_setting = false;
    SettingError bad_code = SettingError::None;
    std::int32_t bad_line = 0;
    double bad_value = 0.0;
    bool overload_warn = false, overload_hold = false;
    double load_rev = 0.0, load_percent = 0.0;
    double predicted_depth_mm = 0.0;
    double depth_ahead_mm = 0.0;           // the stock model's depth ahead of the tool
    double feed_ceiling_mm_per_rev = 0.0;  // feed-forward's ceiling (0: none)
    double specific_force_ratio = 1.0;     // κ: measured load over the handbook law's
    double hardness_estimate = 1.0;        // ĥ = κ^(1/kmp) (the tool-life law)
    bool breakage = false;
    bool tool_data_changed = false;
    OperationRecord op;
    TeachRecord teach;
    bool control_period = false;  // this call ran the control law
  };

  AdaptiveMachine();
  ~AdaptiveMachine();
  AdaptiveMachine(const AdaptiveMachine&) = delete;
  AdaptiveMachine& operator=(const AdaptiveMachine&) = delete;

  void configure(const Params& p);  // throws std::invalid_argument
  // One servo period. Never allocates, throws, locks or logs.
  void update(const Input& in, Output& out) noexcept;
  // Publishes the operation running now (end of the program).
  void end_operation(Output& out) noexcept;
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // The stock model follows `plant` (cutting::LathePlant::follow): a plant of the same blank
  // that the caller cuts at the tool's position of each update(), just before it (rig E: its
  // cutting process). Where it was so, the model takes the plant's cut instead of cutting its
  // own grid again: the same numbers; where not, it cuts its own. No stock model: nothing.
  // After configure(); not real-time (throws std::invalid_argument when the grids differ).
  void follow_stock(const cutting::LathePlant& plant);
  // The stock model has followed the plant at every update() so far.
  [[nodiscard]] bool stock_following() const noexcept { return stock_ && stock_->following(); }
  [[nodiscard]] const AdaptiveFeedController& controller() const noexcept { return ctl_; }
  [[nodiscard]] std::size_t taught_count() const noexcept { return n_taught_; }
  [[nodiscard]] const Taught& taught(std::size_t i) const noexcept { return taught_[i]; }

 private:
  struct OpSettings {
    double limit = 0.0;
    double feed_min = 0.0;
    double feed_max = 0.0;
    int mode = 2;  // 1 off, 2 on, 3 teach (4 resolves to 2 with the limit from the reference)
    double reference = 0.0;  // what overload levels are percentages of
    bool operator==(const OpSettings&) const = default;
  };
  // Tool data under a running program (see the .cpp).
  struct ToolWatch {
    int tool = 0;
    double diameter = 0.0, offset_x = 0.0, offset_z = 0.0;
    double since_change_s = 1e9;
    bool known = false;
    bool update(int t, double d, double ox, double oz, bool feed_move, double dt) noexcept;
  };

  // What control() reads of the load sensor this control period.
  struct LoadReading {
    double load = 0.0;  // sensor 4: the force, or the cutting power with the power sensor
    double rpm = 0.0;   // |n|
    bool feed_block = false;
    bool sensing = true;  // false: the reading cannot be separated now (held, see .cpp)
  };

  [[nodiscard]] const ToolLimits* tool_of(int number) const noexcept;
  Taught* taught_of(int tool, int op) noexcept;
  SettingError resolve(const Input& in, OpSettings& out, double& bad_value) const noexcept;
  void publish_operation(Output& out) noexcept;
  void hold(Output& out) const noexcept;
  double measured_load(const Input& in, bool feed_move, double rpm, double dt, Output& out,
                       bool& sensing) noexcept;
  void control(const Input& in, Output& out, double dt_measured) noexcept;
  void acceleration_power(double rpm, double dt, double nominal_s) noexcept;
  [[nodiscard]] double shaft_power(double drawn, double rpm) const noexcept;
  [[nodiscard]] double model_load(double depth_mm, double feed_mm_per_rev,
                                  double speed_m_per_min) const noexcept;
  double feed_forward(const Input& in, double rpm, bool feed_block, Output& out) noexcept;
  void learn_specific_force(const Input& in, double rpm, double dt, const Output& out) noexcept;
  [[nodiscard]] double hardness_drift(const Output& out) const noexcept;
  // update()'s phases, in the order they run (adaptive_machine.cpp says what each decides).
  bool period_fits(const Input& in, Output& out) noexcept;
  void read_motion(const Input& in, const Output& out) noexcept;
  void apply_settings(const Input& in, Output& out) noexcept;
  void track_operation(const Input& in, Output& out, int opn) noexcept;
  void watch_tool_data(const Input& in, Output& out, bool feed_move, double dt) noexcept;
  void watch_path(const Input& in, Output& out, bool feed_move, double dt) noexcept;
  // control()'s phases, in the order they run.
  AdaptiveFeedController::Input controller_input(const Input& in, Output& out, const LoadReading& r,
                                                 double dt_measured) noexcept;
  void track_contact(const LoadReading& r, double dt, Output& out) noexcept;
  void watch_overload(const Input& in, Output& out) noexcept;
  void teach_in(const LoadReading& r, double dt, Output& out) noexcept;
  [[nodiscard]] double program_feed_factor(const Input& in, double rpm) const noexcept;
  void write_feed(const Input& in, double factor, bool feed_block, bool held, double dt,
                  Output& out) noexcept;
  void write_state(const LoadReading& r, double dt, Output& out) noexcept;
  void write_spindle(const Input& in, bool regulating, Output& out) const noexcept;

  Params p_{};
  AdaptiveFeedController ctl_;
  AdaptiveFeedController::Output co_{};
  AdaptiveFeedController::Params base_{};
  bool speed_law_ = false;
  long every_ = 0;  // servo periods per control period (0: not yet known, −1: not whole)
  long count_ = 0;
  double ctl_elapsed_s_ = 0.0;  // measured time since the last control update
  bool last_reset_ = false;
  double req_prev_ = 0.0, req_stable_ = 0.0;
  double f_word_ = 0.0;
  std::array<ToolLimits, kMaxTools> tools_{};
  std::size_t n_tools_ = 0;
  std::array<Taught, kMaxTaught> taught_{};
  std::size_t n_taught_ = 0;
  OpSettings applied_{};
  bool bad_ = false;
  IdleTare tare_;
  // The spindle's speed over the last servo periods (measured time, ω), for dω/dt.
  static constexpr std::size_t kAccelRing = 32;
  std::array<double, kAccelRing> accel_t_{};
  std::array<double, kAccelRing> accel_w_{};
  std::size_t accel_head_ = 0;
  std::size_t accel_n_ = 0;
  double accel_now_s_ = 0.0;
  double accel_W_ = 0.0;  // J·ω·dω/dt
  double accel_lagged_W_ = 0.0;
  double wdw_ = 0.0, wdw_lagged_ = 0.0;  // ω·dω/dt [rad²/s³], and lagged as the meter
  double inertia_ = 0.0;                 // J in use
  double j_sxy_ = 0.0, j_sxx_ = 0.0, j_seen_s_ = 0.0;
  bool j_ready_ = false;
  double inseparable_left_s_ = 0.0;  // the load reading is held for this much longer
  TeachIn teach_;
  int teach_tool_ = -1, teach_op_ = -1;
  OperationStats stats_;
  int op_line_ = -1, op_tool_ = -1, op_number_ = 0, op_mode_ = 0;
  double op_limit_ = 0.0;
  double op_feed_s_ = 0.0;
  std::uint32_t op_reasons_ = 0;
  std::int32_t op_alarm_ = 0;
  std::int32_t op_seq_ = 0;
  ContactDetector contact_;
  PerRevolutionMean load_rev_;
  bool overload_latched_ = false;
  std::unique_ptr<cutting::LathePlant> stock_;
  cutting::LathePlant::Output stock_out_{};  // the stock model's last step
  bool stock_chip_due_ = false;  // stock_out_'s chip not yet taken since the last cut
  // stock_out_ with the last revolution's chip (LathePlant::chip, taken when first read after
  // a cut: the control period's readers, not every servo period's cut).
  const cutting::LathePlant::Output& stock_chip() noexcept;
  cutting::CuttingModel model_;              // the handbook's law (feed-forward)
  double kappa_ = 1.0;
  bool kappa_learned_ = false;
  double ln_kappa_lag_ = 0.0;  // ln κ lagged by one revolution (its trend)
  double kappa_rate_ = 0.0;    // d ln κ/dt [1/s] while kappa_trend_
  bool kappa_trend_ = false;
  double feed_exponent_ = 0.0;  // y of the law's M ∝ s^y
  // The path's direction: the last 2 µm of travel (a tool standing still keeps it).
  double anchor_x_ = 0.0, anchor_z_ = 0.0, dir_x_ = 0.0, dir_z_ = 0.0;
  bool has_anchor_ = false, has_dir_ = false;
  double ff_ceiling_ = 0.0, ff_hold_s_ = 0.0;  // the last ceiling, held a revolution past the rise
  PathBreakage breakage_;
  bool breakage_latched_ = false;
  ToolWatch tool_watch_;
  bool tool_data_latched_ = false;
  bool tool_data_first_ = false;
  double scale_mismatch_s_ = 0.0;
  double rescale_s_ = 0.0;
};

}  // namespace lathectl::control
