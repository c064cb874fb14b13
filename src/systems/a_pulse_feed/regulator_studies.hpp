#pragma once
// System A's studies of the regulator alone: what the seed's
// advantages 4 (no obliteration) and 5 (coarse manufacturing) rest on, and its characteristic.
//
// Characteristic: the simulated mean flow against formula (1) over the duty range, with and
// without the switching times and overlap; the dead zone and saturation they make, closed form
// against simulation.
//
// Tolerance: manufacturing errors drawn (normal, σ each, [tolerance]) through the pulsed
// regulator's model (hydraulics::PulseRegulator, simulated mean flow with its switching) and
// through a continuous throttle set for the same nominal flow, q = μπd·h·√(2Δp/ρ). Reported:
// the relative flow (= feed) error of each, by error source and all together.
//
// Obliteration: the pulsed regulator and the throttle alone over the scenario's duration, for
// each share η of the silt layer a closing stroke removes ([obliteration_study]); the flow drift
// (mean over the last 5 % against 5–10 %, as feed_drift_pct) of each, with the closed-form
// balance of hydraulics/orifice.hpp beside it.

#include <cstdint>
#include <string>

#include "lathectl/io/runner.hpp"
#include "lathectl/io/study.hpp"
#include "systems/a_pulse_feed/settings.hpp"

namespace lathectl::systems::a_pulse_feed {

// Adds the characteristic's plot and its metrics (summary "metrics": regulator_*) at the
// scenario's slot and pulse frequency. Returns its note on the dead zone and saturation ("" when
// the switching is instantaneous), which the report lists after the other studies' claims.
std::string characteristic_study(const Settings& st, double slot_m, double frequency_Hz,
                                 io::RunOutput& out);

// Adds the study's summary entry ("tolerance_study"), table, plot and claim to `out`/`claims`.
// slot_m: the pulsed regulator's slot in the scenario (the uncontrolled run's fixed actuator).
void tolerance_study(const Settings& st, const ToleranceStudy& spec, double slot_m,
                     std::uint64_t seed, io::RunOutput& out, io::Claims& claims);

// Adds "obliteration_study". slot_m: the pulsed slot; gap_m: the throttle's opening (both set
// for the same flow by the scenario); duration_s: the run's.
void obliteration_study(const Settings& st, double slot_m, double gap_m, double duration_s,
                        io::RunOutput& out, io::Claims& claims);

}  // namespace lathectl::systems::a_pulse_feed
