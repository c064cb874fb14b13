#include "lathectl/dynamics/beam.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <utility>
#include <numbers>
#include <stdexcept>

namespace lathectl::dynamics {

namespace {
void check(const BeamPart& p, double x) {
  if (!(p.length_m > 0.0) || !(p.diameter_m > 0.0) || !(p.youngs_modulus_Pa > 0.0) ||
      !(p.density_kg_per_m3 > 0.0) || !(p.damping_ratio > 0.0))
    throw std::invalid_argument("beam: length, diameter, E, ρ and ζ must be > 0");
  if (!(x > 0.0 && x < p.length_m))
    throw std::invalid_argument("beam: the cutting position must lie between the centres");
}
}  // namespace

BeamModeAt beam_mode_at(const BeamPart& p, double x, int j) noexcept {
  const double pi = std::numbers::pi;
  const double area = pi * p.diameter_m * p.diameter_m / 4.0;
  const double inertia = pi * std::pow(p.diameter_m, 4) / 64.0;
  const double L = p.length_m;
  const double modal_mass = p.density_kg_per_m3 * area * L / 2.0;
  const double w = std::pow(j * pi / L, 2) *
                   std::sqrt(p.youngs_modulus_Pa * inertia / (p.density_kg_per_m3 * area));
  const double phi = std::sin(j * pi * x / L);
  const double phi2 = std::max(phi * phi, 1e-12);
  return {{modal_mass * w * w / phi2, p.damping_ratio, w / (2.0 * pi), p.angle_rad},
          modal_mass / phi2,
          phi};
}

std::vector<Mode> beam_modes_at(const BeamPart& p, double x, int n_modes) {
  check(p, x);
  std::vector<Mode> out;
  for (int j = 1; j <= n_modes; ++j) {
    const BeamModeAt m = beam_mode_at(p, x, j);
    if (std::abs(m.shape) < 1e-6) continue;  // a node at the tool: this mode is not seen
    out.push_back(m.mode);
  }
  return out;
}

double beam_static_stiffness(const BeamPart& p, double x) {
  check(p, x);
  const double inertia = std::numbers::pi * std::pow(p.diameter_m, 4) / 64.0;
  const double L = p.length_m;
  return 3.0 * p.youngs_modulus_Pa * inertia * L / (x * x * (L - x) * (L - x));
}

}  // namespace lathectl::dynamics

namespace lathectl::dynamics {

namespace {

struct Dofs {
  std::vector<int> index;  // global dof (2 per node: w, θ) → reduced index, −1 if held
  int free = 0;
};

Dofs constrain(const BeamModel& m) {
  const std::size_t n = m.nodes_m.size();
  Dofs d;
  d.index.assign(2 * n, 0);
  auto hold = [&](std::size_t node, bool rotation) {
    d.index[2 * node] = -1;
    if (rotation) d.index[2 * node + 1] = -1;
  };
  if (m.supports.headstock != BeamEnd::free) hold(0, m.supports.headstock == BeamEnd::clamped);
  if (m.supports.tailstock != BeamEnd::free) hold(n - 1, m.supports.tailstock == BeamEnd::clamped);
  if (m.supports.steady_rest_m > 0.0) {
    const auto it = std::min_element(m.nodes_m.begin(), m.nodes_m.end(), [&](double a, double b) {
      return std::abs(a - m.supports.steady_rest_m) < std::abs(b - m.supports.steady_rest_m);
    });
    hold(static_cast<std::size_t>(it - m.nodes_m.begin()), false);
  }
  for (auto& i : d.index)
    if (i == 0) i = d.free++;
  return d;
}

void assemble(const BeamModel& m, const Dofs& d, Eigen::MatrixXd& K, Eigen::MatrixXd& M) {
  const auto& p = m.part;
  const double area = std::numbers::pi * p.diameter_m * p.diameter_m / 4.0;
  const double EI = p.youngs_modulus_Pa * std::numbers::pi * std::pow(p.diameter_m, 4) / 64.0;
  const double rhoA = p.density_kg_per_m3 * area;
  K.setZero(d.free, d.free);
  M.setZero(d.free, d.free);
  for (std::size_t e = 0; e + 1 < m.nodes_m.size(); ++e) {
    const double l = m.nodes_m[e + 1] - m.nodes_m[e];
    Eigen::Matrix4d ke, me;
    ke << 12, 6 * l, -12, 6 * l, 6 * l, 4 * l * l, -6 * l, 2 * l * l, -12, -6 * l, 12, -6 * l,
        6 * l, 2 * l * l, -6 * l, 4 * l * l;
    ke *= EI / (l * l * l);
    me << 156, 22 * l, 54, -13 * l, 22 * l, 4 * l * l, 13 * l, -3 * l * l, 54, 13 * l, 156,
        -22 * l, -13 * l, -3 * l * l, -22 * l, 4 * l * l;
    me *= rhoA * l / 420.0;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const int ia = d.index[2 * e + static_cast<std::size_t>(a)];
        const int ib = d.index[2 * e + static_cast<std::size_t>(b)];
        if (ia < 0 || ib < 0) continue;
        K(ia, ib) += ke(a, b);
        M(ia, ib) += me(a, b);
      }
  }
}

// Hermite shape functions of the element holding x: weights of (w_a, θ_a, w_b, θ_b).
std::pair<std::size_t, Eigen::Vector4d> hermite(const BeamModel& m, double x) {
  const auto& n = m.nodes_m;
  auto it = std::upper_bound(n.begin(), n.end(), x);
  std::size_t e = it == n.begin() ? 0 : static_cast<std::size_t>(it - n.begin()) - 1;
  e = std::min(e, n.size() - 2);
  const double l = n[e + 1] - n[e], s = std::clamp((x - n[e]) / l, 0.0, 1.0);
  Eigen::Vector4d N(1 - 3 * s * s + 2 * s * s * s, l * (s - 2 * s * s + s * s * s),
                    3 * s * s - 2 * s * s * s, l * (-s * s + s * s * s));
  return {e, N};
}

}  // namespace

BeamModel beam_model(const BeamPart& part, const BeamSupports& sup, int n_modes, int elements) {
  check(part, 0.5 * part.length_m);
  if (n_modes < 1 || elements < 4)
    throw std::invalid_argument("beam model: at least one mode and four elements");
  if (sup.steady_rest_m < 0.0 || sup.steady_rest_m > part.length_m)
    throw std::invalid_argument("beam model: the steady rest must lie on the part (0 < x ≤ L)");
  const bool rest = sup.steady_rest_m > 0.0;
  const int holds = (sup.headstock == BeamEnd::free ? 0 : 1) + (sup.tailstock == BeamEnd::free ? 0 : 1) +
                    (rest ? 1 : 0);
  if (holds < 2 && sup.headstock != BeamEnd::clamped && sup.tailstock != BeamEnd::clamped)
    throw std::invalid_argument("beam model: the part must be held (a chuck, or two supports)");
  BeamModel m{part, sup, {}, {}, {}};
  for (int k = 0; k <= elements; ++k) m.nodes_m.push_back(part.length_m * k / elements);
  if (rest) {  // a node exactly at the rest
    const auto it = std::lower_bound(m.nodes_m.begin(), m.nodes_m.end(), sup.steady_rest_m);
    if (it == m.nodes_m.end() || std::abs(*it - sup.steady_rest_m) > 1e-12 * part.length_m)
      m.nodes_m.insert(it, sup.steady_rest_m);
  }
  const Dofs d = constrain(m);
  Eigen::MatrixXd K, M;
  assemble(m, d, K, M);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  if (es.info() != Eigen::Success) throw std::invalid_argument("beam model: eigen solve failed");
  const int count = std::min(n_modes, static_cast<int>(d.free));
  for (int j = 0; j < count; ++j) {
    m.omega_rad_s.push_back(std::sqrt(std::max(es.eigenvalues()(j), 0.0)));
    std::vector<double> shape(d.index.size(), 0.0);
    for (std::size_t g = 0; g < d.index.size(); ++g)
      if (d.index[g] >= 0) shape[g] = es.eigenvectors()(d.index[g], j);
    m.shapes.push_back(std::move(shape));
  }
  return m;
}

double beam_model_shape(const BeamModel& m, std::size_t j, double x) {
  const auto [e, N] = hermite(m, x);
  const auto& s = m.shapes.at(j);
  return N(0) * s[2 * e] + N(1) * s[2 * e + 1] + N(2) * s[2 * e + 2] + N(3) * s[2 * e + 3];
}

std::vector<Mode> beam_model_modes_at(const BeamModel& m, double x) {
  std::vector<Mode> out;
  for (std::size_t j = 0; j < m.shapes.size(); ++j) {
    double peak = 0.0;  // the shape's largest nodal displacement, for the node test
    for (std::size_t g = 0; g < m.shapes[j].size(); g += 2) peak = std::max(peak, std::abs(m.shapes[j][g]));
    const double phi = beam_model_shape(m, j, x);
    if (!(std::abs(phi) >= 1e-6 * peak)) continue;  // a node at the tool: not seen
    const double w = m.omega_rad_s[j];
    out.push_back({w * w / (phi * phi), m.part.damping_ratio, w / (2.0 * std::numbers::pi),
                   m.part.angle_rad});
  }
  return out;
}

double beam_model_static_stiffness(const BeamModel& m, double x) {
  const Dofs d = constrain(m);
  Eigen::MatrixXd K, M;
  assemble(m, d, K, M);
  const auto [e, N] = hermite(m, x);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(d.free);
  for (int a = 0; a < 4; ++a) {  // the point load's consistent nodal forces
    const int i = d.index[2 * e + static_cast<std::size_t>(a)];
    if (i >= 0) f(i) += N(a);
  }
  const Eigen::VectorXd u = K.ldlt().solve(f);
  double w = 0.0;
  for (int a = 0; a < 4; ++a) {
    const int i = d.index[2 * e + static_cast<std::size_t>(a)];
    if (i >= 0) w += N(a) * u(i);
  }
  return 1.0 / w;
}

}  // namespace lathectl::dynamics
