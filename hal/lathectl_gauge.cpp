// lathectl_gauge — system D's machine side as a HAL component: seed 003's vibro-contact gauge
// (rectifier, filter, a sequence of thresholds each with its command, the relay's response, the
// backstop, the sensor checks), control::GaugeMachine, the same object `lathectl run` machines its
// parts with. The component is only a map from pins to the machine's Input and Output.
//
//   loadrt lathectl_gauge scenario=PATH size_x_mm=X [period_ns=100000] [rough_factor=4]
//                         [fine_factor=2] [fine_um=60] [spark_um=25] [threshold_V=]
//                         [signal_lost=0.05] [servo_period_ns=1000000]
//                         [stop_latency_periods=0]
//   addf lathectl-gauge base-thread
//
// It samples the generator's signal every period of a thread fast enough for the probe's 2ω
// (the machine asks for 20 samples a period of it at least; 100 µs gives 50 at a 50 Hz supply).
// LinuxCNC's conventions for the commands:
//   feed-scale → motion.adaptive-feed: rough 1, fine fine_factor/rough_factor, spark-out
//                1/rough_factor of the program's F (M52 P1). The steps change the feed inside
//                one plunge without the interpreter's latency.
//   probe      → motion.probe-input: TRUE once the size command has operated (or the backstop or
//                an alarm ended the cut). A G38.2/G38.3 plunge toward the backstop stops there;
//                G38.2 errors if it reaches the backstop untripped (a natural backstop).
//   step       → motion.analog-in-00: the steps operated (M66 E0 L0 reads it into #5399).
//   rearm      ← motion.digital-out-00 (M64/M65 P0): a new part; the relay arms arm_after later.
//   feed-hold  → motion.feed-inhibit: a lost or non-finite signal holds the feed, latched.
//   spindle-revs ← spindle.0.revs (the spindle's encoder, in revolutions; extrapolated between
//                the servo thread's updates) and part-angle-deg (the part's orientation on the
//                spindle): an interrupted part (the scenario's [interruption] with gate) is
//                bridged while an interruption of the drawing is under the probe and guard_ms
//                after; interruptions too close for the bridge alarm gauge_no_round_surface.
// The steps' feeds, fine_um and spark_um default to the scenario's [sequence] (the module
// parameters override them).
// The thresholds are the scenario's: the size threshold as `lathectl run` aims it
// (machine_threshold: (23) on the full model's local line aimed past the first-passage bias, or
// the seed's, or the given one), the earlier ones (23) on the same line for the size where the
// next step starts (target + fine_um, target + spark_um) at the removal rate of the step they end.
// stop_latency_periods × servo_period_ns: how long X goes on at the old feed after a command
// (motion sees the output in its next servo period, X stands still 4 periods after that: 4.1–5.0
// ms over 200 parts, scripts/linuxcnc-gauge-series; the INI's [LATHECTL]STOP_LATENCY_PERIODS =
// 4.5); each command operates that much before t_r, so the axis stands still t_r after the
// crossing on average, as in `lathectl run`.
// Pins and parameters: lathectl_gauge(9).

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/core/parameter_error.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "lathectl_hal.hpp"
#include "pins/gauge.hpp"
#include "systems/d_gauging/machine_params.hpp"
#include "systems/d_gauging/rig.hpp"
#include "systems/d_gauging/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-D vibro-contact gauge (machine side) for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario, "system-D scenario file (TOML): process, transducer, gauge");
LATHECTL_HAL_PARAM(size_x_mm, "machine X [mm] of the tool when the part is at its target size");
LATHECTL_HAL_PARAM(period_ns, "period of the thread this runs in [ns], default 100000");
LATHECTL_HAL_PARAM(rough_factor, "rough feed / the scenario's removal rate, default 4");
LATHECTL_HAL_PARAM(fine_factor, "fine feed / the scenario's removal rate, default 2");
LATHECTL_HAL_PARAM(fine_um, "size above target where the fine feed starts [um], default 60");
LATHECTL_HAL_PARAM(spark_um, "size above target where spark-out starts [um], default 25");
LATHECTL_HAL_PARAM(threshold_V,
                   "the size threshold [V] instead of the scenario's plan "
                   "(\"scenario\": the plan's)");
LATHECTL_HAL_PARAM(servo_period_ns, "motion's servo period [ns], default 1000000");
LATHECTL_HAL_PARAM(stop_latency_periods,
                   "servo periods X goes on at the old feed after a command (mean), default 0: "
                   "each command operates that much before the relay's response");
LATHECTL_HAL_PARAM(signal_lost,
                   "signal lost below this fraction of the free probe's signal, "
                   "default 0.05");

namespace {

constexpr const char* kName = "lathectl_gauge";
constexpr const char* kPrefix = "lathectl-gauge";
using lathectl::control::GaugeMachine;

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_GAUGE_PINS)
  lathectl::hal::MeterPins meter;
};

struct State {
  GaugeMachine machine;
  double feed[4] = {1.0, 0.5, 0.25, 0.0};  // per Command: the adaptive-feed scale
  long period = 100000;
  // The size command's (or the backstop's) moment and the axis' stop after it.
  double size_at = -1.0, last_x = 0.0;
  lathectl::systems::d_gauging::Interruption interruption;  // gate: where they are on the part
  lathectl::systems::d_gauging::SpindleAngle spindle;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::Meter meter;

void update(void*, long period) {
  Pins& p = *pins;
  State& s = *st;
  if (!meter.begin(p.meter, period, s.period))
    return;  // the machine was configured for another sample period
  GaugeMachine::Input in;
  p.read_pins(in, s.machine.output());  // the table's copies (pins/gauge.hpp)
  in.position_m = *p.x_pos * 1e-3;
  const double revs = s.spindle.update(*p.spindle_revs, static_cast<double>(period) * 1e-9);
  if (s.interruption.gate && s.interruption.any())
    in.gate = s.interruption.under(2.0 * std::numbers::pi * revs +
                                   *p.part_angle_deg * std::numbers::pi / 180.0);
  s.machine.update(in);
  const auto& o = s.machine.output();
  p.write_pins(in, o);
  // After the size: the scale of the last feed (the G38 stops on the probe; a retract after it
  // runs at the program's rate, scaled alike until the next part's rearm).
  const auto c = static_cast<std::size_t>(o.command);
  *p.feed_scale = o.size ? s.feed[2] : s.feed[c];
  *p.feed_hold = o.alarm && !o.backstop;  // a backstop ends the cut through the probe
  // Trip-to-stop: the last sample the infeed still moved toward the part (X falling) after the
  // cut had to end, from that moment (stop-latency) and from the crossing (trip-to-stop). X comes
  // from the servo thread: it moves in steps of a servo period.
  const double x = *p.x_pos;
  if (!o.stop) {
    s.size_at = -1.0;
  } else {
    if (s.size_at < 0.0) {
      s.size_at = o.time_s;
      *p.stop_latency = 0.0;
      *p.trip_to_stop = std::isfinite(o.trip_time_s) ? o.time_s - o.trip_time_s : 0.0;
    }
    if (x < s.last_x) {
      *p.stop_latency = o.time_s - s.size_at;
      if (std::isfinite(o.trip_time_s)) *p.trip_to_stop = o.time_s - o.trip_time_s;
    }
  }
  s.last_x = x;
  meter.end(p.meter);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    using lathectl::hal::Error;
    using lathectl::hal::number_param;
    namespace dg = lathectl::systems::d_gauging;
    const auto sc = lathectl::hal::load_system(scenario, dg::kReadSection);
    const auto& d = sc.get<dg::Settings>();
    auto state = std::make_unique<State>();
    const double x_size =
        lathectl::hal::required_param(size_x_mm, "size_x_mm", "machine X at the target size");
    state->period = lathectl::hal::ranged_param(period_ns, "period_ns", 1e5, 1e4, 1e7, "1e4 … 1e7");
    const auto period = static_cast<double>(state->period);
    const double rough = number_param(rough_factor, "rough_factor", d.sequence.rough_factor);
    const double fine = number_param(fine_factor, "fine_factor", d.sequence.fine_factor);
    if (!(rough >= fine && fine >= 1.0))
      throw Error("module parameters: expected rough_factor ≥ fine_factor ≥ 1");
    const double fine_m = number_param(fine_um, "fine_um", d.sequence.fine_m * 1e6) * 1e-6;
    const double spark_m = number_param(spark_um, "spark_um", d.sequence.spark_m * 1e6) * 1e-6;
    if (!(fine_m > spark_m && spark_m > 0.0))
      throw Error("module parameters: expected fine_um > spark_um > 0");
    const double lost = number_param(signal_lost, "signal_lost", 0.05);
    if (!(lost >= 0.0 && lost < 1.0)) throw Error("module parameter signal_lost: expected 0 … 1");
    // The transducer as the run configures it (its free signal, where the filter starts).
    lathectl::sensors::VibroContactGauge gauge;
    dg::configure_transducer(sc, gauge);
    const auto plan = dg::plan_threshold(d, sc.run.step_s);
    const bool given =
        threshold_V != nullptr && *threshold_V != '\0' && std::string(threshold_V) != "scenario";
    double s_size = given ? number_param(threshold_V, "threshold_V", 0.0) : plan.threshold_V;
    const double latency =
        number_param(stop_latency_periods, "stop_latency_periods", 0.0) * 1e-9 *
        static_cast<double>(lathectl::hal::ranged_param(servo_period_ns, "servo_period_ns", 1e6,
                                                        1e4, 1e8, "1e4 … 1e8"));
    // The cycle this machine runs: the scenario's sequence with the module parameters' feeds and
    // sizes (always on: a machine's cycle roughs and fines before size).
    dg::Sequence seq;
    seq.enabled = true;
    seq.rough_factor = rough;
    seq.fine_factor = fine;
    seq.fine_m = fine_m;
    seq.spark_m = spark_m;
    auto pr = d.process;
    state->interruption = pr.interruption;
    GaugeMachine::Params mp;
    try {
      pr.cycle = dg::cycle_for(d.transducer, seq, plan.line, pr, s_size);
      // The size threshold as the run aims it (past the first-passage bias; on this cycle).
      if (!given)
        s_size = dg::machine_threshold(d, pr, plan, sc.run.step_s, sc.run.seed,
                                       sc.run.duration_s)
                     .threshold_V;
      // Machine X [m] of the backstop, where a G38 plunge toward it ends: reached within 1 nm
      // (the trajectory planner's rounding of the programmed X).
      mp = dg::machine_params(pr, gauge, s_size,
                              {.period_s = period * 1e-9,
                               .target_x_m = x_size * 1e-3,
                               .backstop_tolerance_m = 1e-9,
                               .signal_lost = lost,
                               .stop_latency_s = latency});
    } catch (const std::invalid_argument& e) {
      throw Error(e.what());
    }
    // The adaptive-feed scale of each command: its removal rate over rough's (the program's F).
    for (std::size_t i = 0; i < 4; ++i)
      state->feed[i] = pr.cycle.rate_factor[i] / pr.cycle.rate_factor[0];
    try {
      state->machine.configure(mp);
    } catch (const lathectl::core::ParameterError& e) {
      throw Error(std::string(scenario) + ": gauge " + e.parameter() + ": " + e.what());
    }
    Pins& p = lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    static_assert(sizeof p.threshold / sizeof p.threshold[0] == GaugeMachine::kMaxSteps);
    for (std::size_t i = 0; i < GaugeMachine::kMaxSteps; ++i)
      *p.threshold[i] = i < mp.steps.size() ? mp.steps[i].threshold_V : 0.0;
    *p.feed_scale = 1.0;
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
