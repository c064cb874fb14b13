#include "lathectl/sim/rig_b.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace lathectl::sim {

namespace {

constexpr double kPi = std::numbers::pi;

std::vector<Channel> rig_b_channels() {
  return {{"time_s", "s"},
          {"z1_mm", "mm"},
          {"z2_mm", "mm"},
          {"y_um", "um"},
          {"y_highpass_um", "um"},
          {"a0_um", "um"},
          {"omega_d_Hz", "Hz"},
          {"feed1_mm_per_min", "mm/min"},
          {"feed2_mm_per_min", "mm/min"},
          {"feed1_cmd_mm_per_min", "mm/min"},
          {"feed2_cmd_mm_per_min", "mm/min"},
          {"chip1_mm", "mm"},
          {"chip2_mm", "mm"},
          {"depth1_mm", "mm"},
          {"depth2_mm", "mm"},
          {"radial1_N", "N"},
          {"radial2_N", "N"},
          {"cut_power_W", "W"},
          {"cut_power_measured_W", "W"},
          {"spindle_power_W", "W"},
          {"spindle_rpm", "rpm"},
          {"engaged", ""},
          {"reason_code", ""},
          {"S_min_mm_per_min", "mm/min"},
          {"dS_mm_per_min", "mm/min"},
          {"dl_mm", "mm"},
          {"n_s", ""}};
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("rig B: " + what);
}

}  // namespace

double RigB::modal_mass_kg(const dynamics::BeamPart& part, double x_c_m) {
  (void)dynamics::beam_modes_at(part, x_c_m, 1);  // validates
  return dynamics::beam_mode_at(part, x_c_m, 1).mass_kg;
}

void RigB::configure(const RigBConfig& cfg, double dt, double record_interval,
                     double max_duration) {
  require(dt > 0.0 && record_interval >= dt && max_duration > 0.0,
          "dt, record interval and duration must be positive (record interval ≥ dt)");
  require(cfg.modes >= 1 && cfg.modes <= kMaxModes, "modes must be in 1..6");
  const double L_mm = cfg.part.length_m * 1e3;
  require(cfg.z_start_mm > 0.0 && cfg.z_end_mm < L_mm && cfg.z_end_mm > cfg.z_start_mm,
          "the cut must run between the centres: 0 < z_start < z_end < length");
  (void)dynamics::beam_modes_at(cfg.part, cfg.z_start_mm * 1e-3, cfg.modes);  // validates
  require(cfg.part.damping_ratio < 1.0, "the part's damping ratio must be below 1");
  require(cfg.rpm > 0.0 && cfg.feed_mm_per_rev > 0.0, "rpm and feed must be positive");
  require(cfg.depth_mm[0] >= 0.0 && cfg.depth_mm[1] >= 0.0, "depths must be non-negative");
  require(cfg.overlap >= 0.0 && cfg.overlap <= 1.0, "overlap must be in [0, 1]");
  require(cfg.tool2_lag_mm >= 0.0 && cfg.approach_mm >= 0.0 && cfg.idle_block_s >= 0.0,
          "tool2_lag, approach and idle block must be non-negative");
  require(cfg.feed_drive_bandwidth_Hz > 0.0, "feed drive bandwidth must be positive");
  cfg_ = cfg;
  cfg_.cutting.form = cutting::ForceForm::Kienzle;
  cut_.configure(cfg_.cutting);
  dt_ = dt;
  max_t_ = max_duration;
  t_ = 0.0;
  step_ = 0;
  sound_ = true;
  done_ = false;
  t_cut_start_ = engaged_at_ = -1.0;
  theta_ = 0.0;
  record_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(record_interval / dt)));
  chain_every_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1e-4 / dt)));
  control_every_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1e-3 / dt)));

  // Rings over K revolutions of material angle.
  const double tau = 60.0 / cfg.rpm;
  cells_per_rev_ = std::max<std::size_t>(64, static_cast<std::size_t>(std::lround(tau / dt)));
  const int lag_revs = cfg.setup == TwinSetup::DepthDivision
                           ? static_cast<int>(std::lround(cfg.tool2_lag_mm / cfg.feed_mm_per_rev))
                           : 0;
  require(lag_revs <= 200, "tool2_lag_mm is more than 200 revolutions of feed");
  ring_cells_ = cells_per_rev_ * static_cast<std::size_t>(lag_revs + 2);
  require(ring_cells_ <= 4'000'000,
          "the surface memory (revolutions × steps per revolution) exceeds 4e6 cells: raise the "
          "step, the speed, or shorten tool2_lag_mm");
  const std::size_t n_rings = cfg.setup == TwinSetup::DepthDivision ? 2 : 1;
  rings_.assign(n_rings, Ring{std::vector<double>(ring_cells_, 0.0),
                              std::vector<double>(ring_cells_, cfg.z_start_mm)});

  n_tools_ = cfg.setup == TwinSetup::Single ? 1 : 2;
  for (int i = 0; i < 2; ++i) {
    Tool& tl = tools_[i];
    tl = Tool{};
    tl.sigma = i == 0 ? 1.0 : -1.0;
    tl.alpha = i == 0 ? 0.0 : kPi;
    tl.t0_mm = cfg.depth_mm[i];
    tl.z0_mm = cfg.z_start_mm - cfg.approach_mm;
    tl.d_weight = cfg.overlap;
    tl.d_lag_rev = 1.0;
    tl.z_lag_rev = 1.0;
  }
  if (cfg.setup == TwinSetup::FeedDivision) {
    tools_[1].z0_mm -= cfg.tool2_lag_mm;  // a set-up offset: the chips become s/2 ∓ lag
    // One shared layer. In cumulative material-angle cells tool 2 (at π) finds tool 1's pass
    // of half a turn ago in the cell it is at (lag 0); tool 1 finds tool 2's one turn of cells
    // back (lag 1).
    tools_[1].d_lag_rev = 0.0;
    tools_[1].z_lag_rev = 0.0;
  }
  if (cfg.setup == TwinSetup::DepthDivision) {
    Tool& t2 = tools_[1];
    t2.z0_mm -= cfg.tool2_lag_mm;
    t2.write_ring = 1;
    t2.d_ring = 0;
    t2.d_lag_rev = lag_revs;
    t2.d_weight = 1.0;
  }
  for (Tool& tl : tools_) {
    tl.z_mm = tl.z0_mm;
    tl.last_cell = static_cast<long long>(
        std::floor(-tl.alpha / (2.0 * kPi) * static_cast<double>(cells_per_rev_)));
  }

  // Modes at the start position, with the initial disturbance on the first mode.
  for (int j = 0; j < kMaxModes; ++j) q_[j] = qd_[j] = shape_[j] = 0.0;
  modes_at_mm_ = -1e9;
  update_modes();
  q_[0] = cfg.initial_disturbance_um * 1e-6;
  y_ = q_[0];
  fy_ = 0.0;

  cfg_.vibration.sample_period_s = dt * static_cast<double>(chain_every_);
  chain_.configure(cfg_.vibration);
  const double hp = cfg_.vibration.highpass_Hz;
  const double k = std::tan(kPi * hp * dt);
  const double nq = 1.0 / (1.0 + std::numbers::sqrt2 * k + k * k);
  hb0_ = nq;
  hb1_ = -2.0 * nq;
  hb2_ = nq;
  ha1_ = 2.0 * (k * k - 1.0) * nq;
  ha2_ = (1.0 - std::numbers::sqrt2 * k + k * k) * nq;
  hx1_ = hx2_ = hy1_ = hy2_ = y_hp_ = 0.0;

  spindle_.configure(cfg.spindle);
  spindle_.reset(cfg.rpm);
  power_.configure(cfg.power, dt * static_cast<double>(control_every_));
  auto mp = cfg.module;
  mp.period_s = dt * static_cast<double>(control_every_);
  module_.configure(mp);
  mod_out_ = {};
  const double cut_time = (cfg.z_end_mm - cfg.z_start_mm + cfg.approach_mm + cfg.tool2_lag_mm) /
                          (cfg.feed_mm_per_rev * cfg.rpm / 60.0);
  max_t_ = std::min(max_duration, cfg.idle_block_s + 1.5 * cut_time + 1.0);
  const double rows = max_t_ / (dt * static_cast<double>(record_every_)) + 2.0;
  require(rows <= 5e6, "more than 5e6 recorded rows: raise run.record_interval_s");
  rec_ = Recorder(rig_b_channels(), static_cast<std::size_t>(rows));
}

void RigB::update_modes() noexcept {
  const double L = cfg_.part.length_m * 1e3;
  const double x_mm =
      std::clamp(cfg_.modes_follow_tool ? tools_[0].z_mm : cfg_.z_start_mm, 1.0, L - 1.0);
  if (std::abs(x_mm - modes_at_mm_) < 0.5) return;
  modes_at_mm_ = x_mm;
  for (int j = 0; j < cfg_.modes; ++j) {
    const dynamics::BeamModeAt bm = dynamics::beam_mode_at(cfg_.part, x_mm * 1e-3, j + 1);
    // Keep the physical modal amplitude: q = η·φ(x_c).
    if (shape_[j] != 0.0) {
      const double r = bm.shape / shape_[j];
      q_[j] *= r;
      qd_[j] *= r;
    }
    shape_[j] = bm.shape;
    const double wn = 2.0 * kPi * bm.mode.natural_frequency_Hz;
    const double z = bm.mode.damping_ratio;
    const double wd = wn * std::sqrt(1.0 - z * z);
    const double s = z * wn;
    const double e = std::exp(-s * dt_), c = std::cos(wd * dt_), sn = std::sin(wd * dt_);
    phi11_[j] = e * (c + s / wd * sn);
    phi12_[j] = e * sn / wd;
    phi21_[j] = -wn * wn * phi12_[j];
    phi22_[j] = e * (c - s / wd * sn);
    g1_[j] = (1.0 - phi11_[j]) / bm.mode.stiffness_N_per_m;
    g2_[j] = phi12_[j] / bm.mass_kg;
  }
}

double RigB::read(const std::vector<double>& v, double cell) const noexcept {
  const double fl = std::floor(cell);
  const auto m = static_cast<long long>(ring_cells_);
  const long long i = ((static_cast<long long>(fl) % m) + m) % m;
  const double f = cell - fl;
  return v[static_cast<std::size_t>(i)] * (1.0 - f) + v[static_cast<std::size_t>((i + 1) % m)] * f;
}

void RigB::cut(Tool& tl) noexcept {
  const double n_rev = static_cast<double>(cells_per_rev_);
  const double cell = (theta_ - tl.alpha) / (2.0 * kPi) * n_rev;
  // A lag of 0 revolutions reads what was written half a turn ago at this material angle (the
  // other turret's pass): read one cell ahead, past what this tool itself wrote last step.
  auto at = [&](double lag_rev) { return cell - lag_rev * n_rev + (lag_rev == 0.0 ? 1.0 : 0.0); };
  Ring& w = rings_[tl.write_ring];
  const double d_read = read(rings_[tl.d_ring].d, at(tl.d_lag_rev));
  const double z_read = read(w.z, at(tl.z_lag_rev));
  tl.b_mm = tl.t0_mm + (tl.sigma * y_ + tl.d_weight * d_read) * 1e3;
  tl.s_mm = tl.z_mm - z_read;
  tl.cutting = tl.b_mm > 0.0 && tl.s_mm > 0.0;
  if (tl.cutting) {
    const double v = kPi * cfg_.part.diameter_m * spindle_.rpm();  // m/min
    const cutting::Forces f = cut_.forces({tl.b_mm, tl.s_mm, v, 1.0, 1.0});
    tl.fc = f.Pz;
    tl.fp = f.Py;
  } else {
    tl.fc = tl.fp = 0.0;
  }
  // Write the cells swept since the last step: the new surface where the tool cut; where it did
  // not, the surface it met is carried forward (from the cell it reads its chip from; with a lag
  // of 0 that is this cell, which keeps the other turret's surface).
  const auto m = static_cast<long long>(ring_cells_);
  const auto back = static_cast<long long>(tl.z_lag_rev) * static_cast<long long>(cells_per_rev_);
  const auto now = static_cast<long long>(std::floor(cell));
  for (long long c = tl.last_cell + 1; c <= now; ++c) {
    const auto i = static_cast<std::size_t>(((c % m) + m) % m);
    if (tl.cutting) {
      w.d[i] = -tl.sigma * y_;
      w.z[i] = tl.z_mm;
    } else if (back > 0) {
      const auto p = static_cast<std::size_t>((((c - back) % m) + m) % m);
      w.d[i] = w.d[p];
      w.z[i] = w.z[p];
    }
  }
  if (now > tl.last_cell) tl.last_cell = now;
}

bool RigB::step() noexcept {
  if (done_ || t_ >= max_t_ || !sound_) return false;
  const bool idle_block = t_ < cfg_.idle_block_s;
  const bool feed_block = !idle_block;
  if (feed_block && t_cut_start_ < 0.0) t_cut_start_ = t_;

  if (step_ % control_every_ == 0) {
    const double rpm = spindle_.rpm();
    power_.update(spindle_.electrical_power_W(), rpm, idle_block);
    control::ModulatedFeedController::Input in;
    in.a0_m = chain_.a0_m();
    in.omega_d_rad_per_s = chain_.omega_d();
    in.cut_power_W = power_.cutting_W();
    in.speed_m_per_min = kPi * cfg_.part.diameter_m * rpm;
    in.rpm = rpm;
    const double s_prog = cfg_.feed_mm_per_rev * cfg_.rpm;
    in.feed_programmed_mm_per_min[0] = s_prog;
    in.feed_programmed_mm_per_min[1] = n_tools_ == 2 ? s_prog : 0.0;
    in.path_mm[0] = tools_[0].z_mm - tools_[0].z0_mm;
    in.path_mm[1] = tools_[1].z_mm - tools_[1].z0_mm;
    in.feed_block = feed_block;
    in.source = cfg_.source;
    in.turret = cfg_.turret;
    in.programmed = cfg_.programmed;
    (void)module_.update(in, mod_out_);
    if (mod_out_.engaged && engaged_at_ < 0.0) engaged_at_ = t_;
    for (int i = 0; i < 2; ++i)
      tools_[i].cmd_mm_per_min = feed_block && i < n_tools_ ? mod_out_.feed_mm_per_min[i] : 0.0;
  }

  // Feed drives, spindle, cutting position.
  const double a = 1.0 - std::exp(-2.0 * kPi * cfg_.feed_drive_bandwidth_Hz * dt_);
  for (int i = 0; i < n_tools_; ++i) {
    Tool& tl = tools_[i];
    tl.v_mm_per_min += a * (tl.cmd_mm_per_min - tl.v_mm_per_min);
    tl.z_mm += tl.v_mm_per_min / 60.0 * dt_;
  }
  double torque = 0.0;
  for (int i = 0; i < n_tools_; ++i) torque += tools_[i].fc * 0.5 * cfg_.part.diameter_m;
  spindle_.step(dt_, cfg_.rpm, torque);
  theta_ += spindle_.omega() * dt_;
  update_modes();

  // Cutting at each edge, then the part's response to the radial forces.
  fy_ = 0.0;
  for (int i = 0; i < n_tools_; ++i) {
    cut(tools_[i]);
    fy_ -= tools_[i].sigma * tools_[i].fp;
  }
  y_ = 0.0;
  for (int j = 0; j < cfg_.modes; ++j) {
    const double q = phi11_[j] * q_[j] + phi12_[j] * qd_[j] + g1_[j] * fy_;
    const double qd = phi21_[j] * q_[j] + phi22_[j] * qd_[j] + g2_[j] * fy_;
    q_[j] = q;
    qd_[j] = qd;
    y_ += q;
  }
  if (!std::isfinite(y_) || std::abs(y_) > 0.05) sound_ = false;
  const double yh = hb0_ * y_ + hb1_ * hx1_ + hb2_ * hx2_ - ha1_ * hy1_ - ha2_ * hy2_;
  hx2_ = hx1_;
  hx1_ = y_;
  hy2_ = hy1_;
  hy1_ = yh;
  y_hp_ = yh;
  if (step_ % chain_every_ == 0) chain_.update(y_);

  if (step_ % record_every_ == 0) {
    const double cut_power = [&] {
      double p = 0.0;
      const double v = kPi * cfg_.part.diameter_m * spindle_.rpm() / 60.0;
      for (int i = 0; i < n_tools_; ++i) p += tools_[i].fc * v;
      return p;
    }();
    const auto& pl = mod_out_.plan;
    const double row[] = {t_,
                          tools_[0].z_mm,
                          tools_[1].z_mm,
                          y_ * 1e6,
                          y_hp_ * 1e6,
                          chain_.a0_m() * 1e6,
                          chain_.omega_d() / (2.0 * kPi),
                          tools_[0].v_mm_per_min,
                          tools_[1].v_mm_per_min,
                          tools_[0].cmd_mm_per_min,
                          tools_[1].cmd_mm_per_min,
                          tools_[0].cutting ? tools_[0].s_mm : 0.0,
                          tools_[1].cutting ? tools_[1].s_mm : 0.0,
                          tools_[0].cutting ? tools_[0].b_mm : 0.0,
                          tools_[1].cutting ? tools_[1].b_mm : 0.0,
                          tools_[0].fp,
                          tools_[1].fp,
                          cut_power,
                          power_.cutting_W(),
                          spindle_.electrical_power_W(),
                          spindle_.rpm(),
                          mod_out_.engaged ? 1.0 : 0.0,
                          static_cast<double>(mod_out_.reason),
                          pl.s_min_mm_per_min,
                          pl.ds_mm_per_min,
                          pl.dl_mm,
                          static_cast<double>(pl.n_s)};
    rec_.push_row(row);
  }
  t_ += dt_;
  ++step_;
  if (tools_[0].z_mm >= cfg_.z_end_mm && (n_tools_ == 1 || tools_[1].z_mm >= cfg_.z_end_mm))
    done_ = true;
  return !done_;
}

void RigB::run() noexcept {
  while (step()) {
  }
}

}  // namespace lathectl::sim
