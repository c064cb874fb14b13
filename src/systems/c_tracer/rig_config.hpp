#pragma once
// Rig C's configuration (systems/c_tracer/rig.hpp): what the settings hold (settings.hpp) and the
// rig runs. Here, apart from the rig, so that the settings library (what reads a scenario)
// includes nothing of the rig's layer (tests/layers/layer_order.cmake).

#include <string>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/hydraulics/tracer.hpp"

namespace lathectl::systems::c_tracer {

struct TracerFeature {
  std::string kind;        // "line", "cone", "step", "arc"
  double x_start_m = 0.0;  // where it starts on the template
  double x_end_m = 0.0;
};

struct RigConfig {
  hydraulics::TemplateProfile profile;
  std::vector<TracerFeature> features;
  double beta_rad = 1.0;           // guide inclination β
  double feed_m_per_rev = 0.2e-3;  // s
  double spindle_rpm = 500.0;      // n
  bool nonlinear = false;
  hydraulics::TracerLinear linear;  // used when !nonlinear (and reported as the linearisation)
  // nonlinear servo
  double supply_Pa = 4e6;
  double discharge_coefficient = 0.65;
  double area_gradient_m = 0.01;  // w: spool port width
  double density_kg_per_m3 = 870.0;
  double overlap_m = 0.0;
  double clearance_leak_m3_per_s_Pa = 1e-12;  // K_c
  double piston_area_m2 = 20e-4;
  double total_volume_m3 = 200e-6;
  double bulk_modulus_Pa = 1.4e9;
  // Friction: none unless [friction] gives it (the scenario reader's defaults; before one default
  // per key, a scenario without the table got 200 N, 200 N and 2000 N·s/m, one with an empty table
  // zeros).
  double coulomb_N = 0.0;
  double static_N = 0.0;  // ≥ coulomb_N; the reader's default is coulomb_N
  double stribeck_velocity_m_per_s = 1e-4;
  double viscous_N_s_per_m = 0.0;
  // cutting (nonlinear model); blank diameter ≤ 0 → constant load P0 = linear.P0_N instead
  cutting::CuttingModel::Params cutting;
  double blank_diameter_m = 0.0;
};

}  // namespace lathectl::systems::c_tracer
