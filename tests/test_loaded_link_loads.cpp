// Loads along links and self-weight in the loaded mode (docs/theory.md §15.9): the clamp
// wrenches at the unloaded pose against the linear fixed-end forces, their derivatives against
// finite differences, tiny loads against the linear mode, a cantilever under a large uniform
// load against its elastica, a column under its own weight against Greenhill's load, and the
// balance of the reactions with the loads where the deformed structure carries them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include "command_line.hpp"
#include "elements/beam_element.hpp"
#include "elements/beam_loads.hpp"
#include "elements/finite_rotation.hpp"
#include "elements/loaded_blocks.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/model.hpp"

namespace stiffmsa {
namespace {

using detail::EndState;
using detail::LoadAlongLink;
using Vec12 = Eigen::Matrix<double, 12, 1>;

SolveOptions loaded_options() {
  SolveOptions options;
  options.mode = AnalysisMode::loaded;
  return options;
}

// ---- the block: clamp wrenches and their derivatives ----------------------------------------

// A link block of 12 rows that contributes nothing: what remains is the loads' part.
class NoRows final : public detail::LoadedBlock {
 public:
  detail::Index equation_count() const override { return 12; }
  const std::vector<int>& ends() const override { return ends_; }
  void evaluate(const detail::LoadedInputs&, Eigen::Ref<VecX> residual,
                MatX* tangent) const override {
    residual.setZero();
    if (tangent) tangent->setZero(12, 24);
  }

 private:
  std::vector<int> ends_{0, 1};
};

const Vec3 kFrom(0.2, -0.1, 0.3), kTo(1.1, 0.5, 0.9);

Link timoshenko_beam() {
  BeamLink beam{Material{2.1e11, 0.3, std::nullopt, std::nullopt}, Section::rect(0.03, 0.08), true,
                std::nullopt};
  return Link{"beam", "a", "b", beam, {}};
}

std::vector<LoadAlongLink> some_loads() {
  return {DistributedLinkLoad{Vec3(100, -300, 50), Vec3(-40, 200, 700)},
          PointLinkLoad{Vec3(30, 80, -60), Vec3(12, -7, 25), 0.3},
          PointLinkLoad{Vec3(-20, 10, 90), Vec3::Zero(), 0.85}};
}

// The residual of the loads' part alone at ends `i`, `j` (wrenches zero): minus the clamp
// wrenches.
VecX residual_of(const detail::LoadedBlock& block, const EndState& i, const EndState& j,
                 MatX* tangent = nullptr) {
  const std::vector<EndState> ends{i, j};
  const std::vector<Vec6> external(2, Vec6::Zero());
  VecX r(12);
  block.evaluate(detail::LoadedInputs{ends, external, 1.0}, r, tangent);
  return r;
}

TEST(LoadedLinkLoads, AtTheUnloadedPoseABeamsClampWrenchesAreItsExactFixedEndForces) {
  const Link link = timoshenko_beam();
  const auto block =
      detail::with_loads_along(std::make_unique<NoRows>(), link, kFrom, kTo, some_loads());
  EndState i, j;
  i.position = kFrom;
  j.position = kTo;
  const VecX clamp = -residual_of(*block, i, j);
  // The linear mode's: the fixed-end forces of §12 in the beam's axes, turned to global.
  const auto& beam = std::get<BeamLink>(link.kind);
  const Mat3 axes = detail::link_axes(kFrom, kTo, std::nullopt);
  const detail::BeamConstants c = detail::beam_constants(beam, (kTo - kFrom).norm());
  ASSERT_GT(c.phi_y, 1e-3);  // shear counts
  Vec12 expected = Vec12::Zero();
  for (const LoadAlongLink& load : some_loads()) {
    detail::BeamLoad local;
    if (const auto* q = std::get_if<DistributedLinkLoad>(&load))
      local = detail::DistributedLoad{axes * q->from, axes * q->to};
    else {
      const auto& p = std::get<PointLinkLoad>(load);
      local = detail::PointLoad{axes * p.force, axes * p.moment, p.position};
    }
    const Vec12 f = detail::beam_fixed_end_forces(c, local);
    for (int part = 0; part < 4; ++part)
      expected.segment<3>(3 * part) += axes.transpose() * f.segment<3>(3 * part);
  }
  EXPECT_LT((clamp - expected).norm(), 1e-12 * expected.norm()) << clamp.transpose() << "\n"
                                                                << expected.transpose();
}

TEST(LoadedLinkLoads, ARigidLinksLoadRidesWithItAndBalancesItsEnds) {
  const Link link{"rigid", "a", "b", RigidLink{}, {}};
  const auto block =
      detail::with_loads_along(std::make_unique<NoRows>(), link, kFrom, kTo, some_loads());
  EndState i, j;
  i.position = kFrom + Vec3(0.01, 0.02, -0.03);
  i.rotation = detail::rotation_matrix(Vec3(0.3, -0.2, 0.5));
  j.position = i.position + i.rotation * (kTo - kFrom);
  j.rotation = i.rotation;
  const VecX r = residual_of(*block, i, j);
  // Rows 7–12 hold the loads' resultant and its moment about x_i at their turned places.
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  const Vec3 arm = i.rotation * (kTo - kFrom);
  const double length = (kTo - kFrom).norm();
  for (const LoadAlongLink& load : some_loads()) {
    if (const auto* q = std::get_if<DistributedLinkLoad>(&load)) {
      // Simpson's rule is exact for the linear load's moment (degree 2).
      for (const auto& [xi, weight] : {std::pair{0.0, 1.0}, {0.5, 4.0}, {1.0, 1.0}}) {
        const Vec3 per_length = q->from + xi * (q->to - q->from);
        force += weight / 6 * length * per_length;
        moment += weight / 6 * length * (xi * arm).cross(per_length);
      }
    } else {
      const auto& p = std::get<PointLinkLoad>(load);
      force += p.force;
      moment += (p.position * arm).cross(p.force) + p.moment;
    }
  }
  EXPECT_LT(r.head<6>().norm(), 1e-15);
  EXPECT_LT((r.segment<3>(6) - force).norm(), 1e-12 * force.norm());
  EXPECT_LT((r.segment<3>(9) - moment).norm(), 1e-12 * moment.norm());
}

// Two link ends moved and turned well away from kFrom and kTo: a deformed state.
std::pair<EndState, EndState> deformed_ends() {
  EndState i, j;
  i.position = kFrom + Vec3(0.05, -0.02, 0.03);
  i.rotation = detail::rotation_matrix(Vec3(0.25, -0.4, 0.1));
  j.position = kTo + Vec3(-0.1, 0.07, 0.12);
  j.rotation = detail::rotation_matrix(Vec3(-0.3, 0.2, 0.45));
  return {i, j};
}

// The tangent of the loads' rows at a deformed state against central differences of the
// residual in each increment (δx; δθ with R ← exp([δθ×])·R).
void expect_tangent_is_the_derivative(const Link& link) {
  SCOPED_TRACE(link.name);
  const auto block =
      detail::with_loads_along(std::make_unique<NoRows>(), link, kFrom, kTo, some_loads());
  const auto [i, j] = deformed_ends();
  MatX tangent;
  residual_of(*block, i, j, &tangent);
  constexpr double h = 1e-6;
  MatX differences = MatX::Zero(12, 24);
  for (int end = 0; end < 2; ++end)
    for (int c = 0; c < 6; ++c) {
      auto moved = [&](double step) {
        EndState a = i, b = j;
        EndState& s = end == 0 ? a : b;
        if (c < 3)
          s.position[c] += step;
        else
          s.rotation = detail::rotation_matrix(step * Vec3::Unit(c - 3)) * s.rotation;
        return residual_of(*block, a, b);
      };
      differences.col(12 * end + c) = (moved(h) - moved(-h)) / (2 * h);
    }
  ASSERT_GT(tangent.norm(), 1.0);  // the load stiffness is there
  EXPECT_LT((tangent - differences).norm(), 1e-7 * tangent.norm()) << "tangent\n"
                                                                   << tangent << "\ndifferences\n"
                                                                   << differences;
  // No column of the wrenches: the loads' part does not depend on them.
  EXPECT_EQ(tangent.middleCols<6>(6).norm() + tangent.middleCols<6>(18).norm(), 0.0);
}

TEST(LoadedLinkLoads, TheLoadStiffnessIsTheExactDerivativeOfTheClampWrenches) {
  expect_tangent_is_the_derivative(timoshenko_beam());
  Link euler = timoshenko_beam();
  std::get<BeamLink>(euler.kind).shear = false;
  euler.name = "euler-bernoulli";
  expect_tangent_is_the_derivative(euler);
  expect_tangent_is_the_derivative(Link{"rigid", "a", "b", RigidLink{}, {}});
}

// ---- tiny loads give the linear answers -----------------------------------------------------

Model scaled(Model m, double factor) {
  auto scale_link_loads = [&](std::vector<LinkLoad>& loads) {
    for (LinkLoad& l : loads) {
      if (auto* q = std::get_if<DistributedLinkLoad>(&l.load)) {
        q->from *= factor;
        q->to *= factor;
      } else {
        auto& p = std::get<PointLinkLoad>(l.load);
        p.force *= factor;
        p.moment *= factor;
      }
    }
  };
  for (Load& l : m.loads) l.wrench *= factor;
  scale_link_loads(m.link_loads);
  if (m.gravity) *m.gravity *= factor;
  for (LoadCase& c : m.load_cases) {
    for (Load& l : c.loads) l.wrench *= factor;
    scale_link_loads(c.link_loads);
    if (c.gravity) *c.gravity *= factor;
  }
  for (Support& s : m.supports)
    if (s.displacement) *s.displacement *= factor;
  return m;
}

// The largest relative difference, over the load cases, of the loaded results from the linear
// ones: every link end's deflection and wrench, every reaction and every internal force, each
// against the largest of its kind.
double largest_difference(const Result& loaded) {
  double worst = 0;
  auto compare = [&](const Result& r) {
    const Result& linear = *r.linear;
    double deflection = 0, wrench = 0, reaction = 0, internal = 0;
    for (const LinkResult& l : linear.links) {
      for (const LinkEndResult* e : {&l.from, &l.to}) {
        deflection = std::max(deflection, e->deflection->norm());
        wrench = std::max(wrench, e->wrench->norm());
      }
      for (const InternalForces& f : l.internal_forces)
        internal = std::max(internal, f.forces.norm());
    }
    for (const SupportResult& s : linear.supports)
      reaction = std::max(reaction, s.reaction->norm());
    for (std::size_t l = 0; l < r.links.size(); ++l) {
      const LinkResult &a = r.links[l], &b = linear.links[l];
      worst = std::max({worst, (*a.from.deflection - *b.from.deflection).norm() / deflection,
                        (*a.to.deflection - *b.to.deflection).norm() / deflection,
                        (*a.from.wrench - *b.from.wrench).norm() / wrench,
                        (*a.to.wrench - *b.to.wrench).norm() / wrench});
      EXPECT_EQ(a.internal_forces.size(), b.internal_forces.size());
      for (std::size_t k = 0; k < a.internal_forces.size(); ++k)
        worst = std::max(
            worst, (a.internal_forces[k].forces - b.internal_forces[k].forces).norm() / internal);
    }
    for (std::size_t s = 0; s < r.supports.size(); ++s)
      worst = std::max(worst,
                       (*r.supports[s].reaction - *linear.supports[s].reaction).norm() / reaction);
  };
  compare(loaded);
  for (const Result& c : loaded.load_cases) compare(c);
  return worst;
}

TEST(LoadedLinkLoads, TinyLoadsAlongLinksAndSelfWeightGiveTheLinearResults) {
  // The portal frame: a linearly varying wind load, a settlement, a uniform snow load, a point
  // load on the beam and the frame's own weight, in four cases.
  const Model file =
      load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/portal-frame-load-cases.yaml");
  double previous = 0;
  for (const double factor : {1e-2, 1e-3, 1e-4}) {
    const double difference = largest_difference(solve(scaled(file, factor), loaded_options()));
    std::printf("loads times %g: loaded results within %.3e of the linear ones\n", factor,
                difference);
    EXPECT_LT(difference, 2e-2 * factor) << factor;
    // The difference is the nonlinear part: it shrinks as the loads.
    if (previous > 0) EXPECT_NEAR(previous / difference, 10.0, 0.5) << factor;
    previous = difference;
  }
}

// ---- a cantilever under a large uniform dead load: the elastica ------------------------------

// A cantilever of unit length along x, clamped at s = 0, under a dead load q per unit length
// along −y. With θ(s) its tangent's angle, E·I·θ'(s) is the moment of the load beyond s about
// the section, −q·∫ₛ¹ (x(t) − x(s)) dt, so θ'' = α·(1 − s)·cos θ with α = q·L³/(E·I),
// θ(0) = 0, θ'(1) = 0; x' = cos θ, y' = sin θ. Shooting on θ'(0) with classical Runge–Kutta.
struct ElasticaState {
  double theta, kappa, x, y;
};

ElasticaState integrate(double alpha, double start_curvature, int steps) {
  auto rate = [&](double s, const ElasticaState& e) {
    return ElasticaState{e.kappa, alpha * (1 - s) * std::cos(e.theta), std::cos(e.theta),
                         std::sin(e.theta)};
  };
  auto plus = [](const ElasticaState& a, const ElasticaState& b, double h) {
    return ElasticaState{a.theta + h * b.theta, a.kappa + h * b.kappa, a.x + h * b.x,
                         a.y + h * b.y};
  };
  ElasticaState e{0, start_curvature, 0, 0};
  const double h = 1.0 / steps;
  for (int k = 0; k < steps; ++k) {
    const double s = k * h;
    const ElasticaState k1 = rate(s, e), k2 = rate(s + h / 2, plus(e, k1, h / 2)),
                        k3 = rate(s + h / 2, plus(e, k2, h / 2)), k4 = rate(s + h, plus(e, k3, h));
    e.theta += h / 6 * (k1.theta + 2 * k2.theta + 2 * k3.theta + k4.theta);
    e.kappa += h / 6 * (k1.kappa + 2 * k2.kappa + 2 * k3.kappa + k4.kappa);
    e.x += h / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x);
    e.y += h / 6 * (k1.y + 2 * k2.y + 2 * k3.y + k4.y);
  }
  return e;
}

constexpr int kElasticaSteps = 4000;

ElasticaState elastica(double alpha) {
  // E·I·θ'(0) = −q·∫x dt lies in [−α/2, 0]; θ'(1) grows with θ'(0): bisection.
  double low = -alpha / 2, high = 0;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (low + high);
    (integrate(alpha, mid, kElasticaSteps).kappa > 0 ? high : low) = mid;
  }
  return integrate(alpha, 0.5 * (low + high), kElasticaSteps);
}

TEST(UniformElastica, ReferenceMatchesTheLinearCantileverAndIsConverged) {
  // Small α: the tip deflects by −α/8 and turns by −α/6 (q·L⁴/(8·E·I), q·L³/(6·E·I)).
  const ElasticaState small = elastica(1e-4);
  EXPECT_NEAR(small.y, -1e-4 / 8, 1e-12);
  EXPECT_NEAR(small.theta, -1e-4 / 6, 1e-12);
  const ElasticaState coarse = integrate(5.0, -2.0, kElasticaSteps),
                      fine = integrate(5.0, -2.0, 2 * kElasticaSteps);
  EXPECT_NEAR(coarse.y, fine.y, 1e-13);
  EXPECT_NEAR(coarse.theta, fine.theta, 1e-13);
}

Model uniformly_loaded_cantilever(int n, double load) {
  Model m;
  m.name = "uniform-elastica";
  const Material material{1e9, 0.3, std::nullopt, std::nullopt};
  const Section section = Section::generic(1e3, 1e-6, 1e-6, 2e-6);  // E·I = 1000, E·A = 1e12
  for (int k = 0; k <= n; ++k) m.add_point("p" + std::to_string(k), Vec3(double(k) / n, 0, 0));
  for (int k = 0; k < n; ++k) {
    m.add_beam("b" + std::to_string(k), "p" + std::to_string(k), "p" + std::to_string(k + 1),
               material, section);
    m.add_link_load("b" + std::to_string(k),
                    DistributedLinkLoad{Vec3(0, -load, 0), Vec3(0, -load, 0)});
  }
  m.add_support("clamp", "p0", {}, Connection::rigid());
  m.add_end_effector("tip", "p" + std::to_string(n));
  return m;
}

double uniform_tip_error(int n, double alpha) {
  const double ei = 1e3;
  const Result r = solve(uniformly_loaded_cantilever(n, alpha * ei), loaded_options());
  const ElasticaState exact = elastica(alpha);
  const Vec6 d = *r.end_effector("tip").deflection;
  return std::max(
      {std::abs(d[0] - (exact.x - 1)), std::abs(d[1] - exact.y), std::abs(d[5] - exact.theta)});
}

TEST(LoadedLinkLoads, CantileverUnderALargeUniformDeadLoadConvergesToItsElastica) {
  for (const double alpha : {1.0, 5.0, 15.0}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    const ElasticaState exact = elastica(alpha);
    const double e8 = uniform_tip_error(8, alpha), e16 = uniform_tip_error(16, alpha),
                 e32 = uniform_tip_error(32, alpha), e64 = uniform_tip_error(64, alpha);
    std::printf(
        "q L^3/EI %g (tip turned %.3f rad): tip errors at 8, 16, 32, 64 elements %.3e %.3e "
        "%.3e %.3e\n",
        alpha, exact.theta, e8, e16, e32, e64);
    EXPECT_GT(e8 / e16, 8.0);
    EXPECT_GT(e16 / e32, 8.0);
    EXPECT_LT(e32, 1e-6);
  }
}

// ---- a column under its own weight: Greenhill -----------------------------------------------

// A clamped–free vertical column whose own weight is `factor` times Greenhill's critical weight
// q·L³/(E·I) = 7.8373 about its weak axis (of a 20 × 40 mm bar), nearly inextensible as
// Greenhill's column is (a large area: the bar's own would shorten it by 5e-4 under this
// weight, which raises the critical weight by about as much).
constexpr double kGreenhill = 7.837347;  // the first root of J₋₁/₃(2/3·√(q·L³/(E·I)))

Model heavy_column(double factor, int n) {
  Model m;
  m.name = "heavy-column";
  const double e = 2.1e11, b = 0.02, h = 0.04, length = 1, density = 7850, area = 1.0;
  const double weak = h * b * b * b / 12, strong = b * h * h * h / 12;
  const Section section = Section::generic(area, strong, weak, weak + strong);
  for (int k = 0; k <= n; ++k) m.add_point("p" + std::to_string(k), Vec3(0, 0, length * k / n));
  for (int k = 0; k < n; ++k)
    m.add_beam("c" + std::to_string(k), "p" + std::to_string(k), "p" + std::to_string(k + 1),
               Material{e, 0.3, std::nullopt, density}, section);
  m.add_support("base", "p0", {}, Connection::rigid());
  const double q = factor * kGreenhill * e * weak / (length * length * length);
  m.gravity = Vec3(0, 0, -q / (density * area));
  m.add_end_effector("top", "p" + std::to_string(n));
  return m;
}

// The load factor at which the loaded mode stops a column of n elements under twice Greenhill's
// weight (the last equilibrium reached, within 1e-4 of the load below the critical point).
double stopping_factor(int n) {
  try {
    solve(heavy_column(2.0, n), loaded_options());
  } catch (const NoEquilibriumError& e) {
    std::printf("%d elements: %s\n", n, e.what());
    return e.load_factor();
  }
  ADD_FAILURE() << "a column at twice Greenhill's weight was solved";
  return 0;
}

TEST(LoadedLinkLoads, ColumnUnderItsOwnWeightStopsAtGreenhillsLoad) {
  // Below: solved, and softer sideways than the linear column (its weak axis).
  const Result below = solve(heavy_column(0.5, 16), loaded_options());
  double ratio = 0;
  for (int axis : {0, 1})
    ratio = std::max(ratio, (*below.end_effector("top").compliance)(axis, axis) /
                                (*below.linear->end_effector("top").compliance)(axis, axis));
  EXPECT_GT(ratio, 1.5);
  // The linear eigenproblem (§14) agrees to its own discretisation: it takes each element's
  // axial force as constant (measured 1.6e-3 low at 16 elements).
  ASSERT_TRUE(below.critical_load && below.critical_load->factor);
  std::printf("half Greenhill's weight: sway compliance x %.3f, linear critical factor %.6f\n",
              ratio, *below.critical_load->factor);
  EXPECT_NEAR(*below.critical_load->factor, 2.0, 4e-3);
  // Beyond: the path stops at λ = 1/2 of twice the critical weight, its last equilibrium within
  // the bracket's width (2⁻¹⁴ = 6.1e-5 of the load) below it, from 8 elements on.
  for (const int n : {8, 16}) {
    const double reached = stopping_factor(n);
    EXPECT_LE(reached, 0.5) << n;
    EXPECT_GT(reached, 0.5 - 6.2e-5) << n;
  }
}

// ---- equilibrium in the deformed geometry ---------------------------------------------------

// An L-shaped frame of beams under its own weight, a load along its arm, a point force and
// moment on its column and, on a rigid bracket at the arm's end, a distributed and a point load
// and a load at its tip, large enough to turn it by tenths of a radian.
Model bent_frame() {
  Model m;
  m.name = "bent-frame";
  const Material steel{2.1e11, 0.3, std::nullopt, 7850};
  const Section rod = Section::circle(0.02);
  const int n = 4;
  for (int k = 0; k <= n; ++k) m.add_point("c" + std::to_string(k), Vec3(0, 0, double(k) / n));
  for (int k = 1; k <= n; ++k) m.add_point("a" + std::to_string(k), Vec3(double(k) / n, 0, 1));
  m.add_point("tip", Vec3(1, 0.3, 1));
  for (int k = 0; k < n; ++k) {
    m.add_beam("column" + std::to_string(k), "c" + std::to_string(k), "c" + std::to_string(k + 1),
               steel, rod);
    m.add_beam("arm" + std::to_string(k), k == 0 ? "c4" : "a" + std::to_string(k),
               "a" + std::to_string(k + 1), steel, rod);
    m.add_link_load("arm" + std::to_string(k),
                    DistributedLinkLoad{Vec3(0, 30, -40), Vec3(0, 40, -60)});
  }
  m.add_link_load("column1", PointLinkLoad{Vec3(80, -20, 0), Vec3(5, 10, -8), 0.3});
  m.add_rigid_link("bracket", "a4", "tip");
  m.add_link_load("bracket", DistributedLinkLoad{Vec3(0, 0, -300), Vec3(0, 0, -100)});
  m.add_link_load("bracket", PointLinkLoad{Vec3(50, 0, -50), Vec3(0, 4, 0), 0.4});
  m.add_support("base", "c0", {}, Connection::rigid());
  Vec6 w;
  w << 0, 20, -60, 3, 0, 0;
  m.add_load("tip", std::nullopt, w);
  m.gravity = Vec3(0, 0, -9.81);
  m.add_end_effector("tip", "tip");
  return m;
}

// A load's resultant [F; M about the origin] where the deformed link carries it: a beam's
// points x(ξ) = x_i + ξ·(x_j − x_i) + L·(H_i(ξ)·t_i⊥ + H_j(ξ)·t_j⊥), the cubic with the end
// slopes t⊥ (the ends' turned unloaded axis, across the chord; Euler–Bernoulli shapes
// H_i = ξ − 2ξ² + ξ³, H_j = −ξ² + ξ³); a rigid link's x_i + ξ·R_i·d0.
struct Placed {
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
};

Placed placed(const Link& link, const Vec3& from, const Vec3& to, const LinkResult& r,
              const LinkLoad& load) {
  const Vec3 xi = from + r.from.deflection->head<3>(), xj = to + r.to.deflection->head<3>();
  const Mat3 ri = detail::rotation_matrix(r.from.deflection->tail<3>());
  const Mat3 rj = detail::rotation_matrix(r.to.deflection->tail<3>());
  const double length = (to - from).norm();
  const Vec3 n0 = (to - from) / length, chord = xj - xi, e1 = chord.normalized();
  auto across = [&](const Vec3& t) { return t - t.dot(e1) * e1; };
  const Vec3 ti = across(ri * n0), tj = across(rj * n0);
  auto at = [&](double s) -> Vec3 {
    if (std::holds_alternative<RigidLink>(link.kind)) return xi + s * (ri * (to - from));
    return xi + s * chord + length * ((s - 2 * s * s + s * s * s) * ti + (-s * s + s * s * s) * tj);
  };
  Placed p;
  if (const auto* q = std::get_if<DistributedLinkLoad>(&load.load)) {
    // Five Gauss points: exact for the cubic times the linear load.
    const double nodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                             0.9061798459386640};
    const double weights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
    for (int g = 0; g < 5; ++g) {
      const double s = (1 + nodes[g]) / 2;
      const Vec3 f = weights[g] / 2 * length * (q->from + s * (q->to - q->from));
      p.force += f;
      p.moment += at(s).cross(f);
    }
  } else {
    const auto& point = std::get<PointLinkLoad>(load.load);
    p.force = point.force;
    p.moment = at(point.position).cross(point.force) + point.moment;
  }
  return p;
}

TEST(LoadedLinkLoads, ReactionsBalanceTheLoadsWhereTheDeformedFrameCarriesThem) {
  const Model m = bent_frame();
  const Result r = solve(m, loaded_options());
  // Large: the tip has turned by tenths of a radian.
  ASSERT_GT(r.end_effector("tip").deflection->tail<3>().norm(), 0.1);
  ASSERT_LT(r.end_effector("tip").deflection->tail<3>().norm(), 1.0);
  auto point_of = [&](const std::string& name) {
    for (const Point& p : m.points)
      if (p.name == name) return p.position;
    throw std::runtime_error("no point " + name);
  };
  // Every load along a link, self-weight as a uniform load on each beam.
  std::vector<LinkLoad> loads = m.link_loads;
  for (const Link& link : m.links)
    if (const auto* beam = std::get_if<BeamLink>(&link.kind)) {
      const Vec3 weight =
          *beam->material.density * 3.14159265358979323846 * 0.02 * 0.02 / 4 * *m.gravity;
      loads.push_back(LinkLoad{link.name, DistributedLinkLoad{weight, weight}, {}});
    }
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  double force_scale = 0, moment_scale = 0;
  auto add = [&](const Vec3& f, const Vec3& mo) {
    force += f;
    moment += mo;
    force_scale += f.norm();
    moment_scale += mo.norm();
  };
  for (std::size_t l = 0; l < m.links.size(); ++l) {
    const Link& link = m.links[l];
    const LinkResult& lr = r.links[l];
    const Vec3 from = point_of(link.from), to = point_of(link.to);
    // Each link balances its own loads with its end wrenches (true ones, about its ends).
    Vec3 link_force = lr.from.wrench->head<3>() + lr.to.wrench->head<3>();
    const Vec3 xi = from + lr.from.deflection->head<3>(), xj = to + lr.to.deflection->head<3>();
    Vec3 link_moment = lr.from.wrench->tail<3>() + xi.cross(lr.from.wrench->head<3>()) +
                       lr.to.wrench->tail<3>() + xj.cross(lr.to.wrench->head<3>());
    double scale = lr.from.wrench->head<3>().norm() + lr.to.wrench->head<3>().norm();
    for (const LinkLoad& load : loads)
      if (load.link == link.name) {
        const Placed p = placed(link, from, to, lr, load);
        add(p.force, p.moment);
        link_force += p.force;
        link_moment += p.moment;
      }
    EXPECT_LT(link_force.norm(), 1e-10 * scale) << link.name;
    EXPECT_LT(link_moment.norm(), 1e-10 * scale * 2) << link.name;
  }
  const Vec6 tip_load = m.loads.front().wrench;
  const Vec3 tip = point_of("tip") + r.end_effector("tip").deflection->head<3>();
  add(tip_load.head<3>(), tip_load.tail<3>() + tip.cross(tip_load.head<3>()));
  const Vec6 reaction = *r.support("base").reaction;  // about the base, which stays at 0
  add(reaction.head<3>(), reaction.tail<3>());
  std::printf(
      "tip turned by %.3f rad; reactions and loads balance to %.1e (forces), %.1e "
      "(moments)\n",
      r.end_effector("tip").deflection->tail<3>().norm(), force.norm() / force_scale,
      moment.norm() / moment_scale);
  EXPECT_LT(force.norm(), 1e-10 * force_scale);
  EXPECT_LT(moment.norm(), 1e-10 * moment_scale);
  // And they differ from the linear reaction by the deformation's moment arms.
  EXPECT_GT((reaction - *r.linear->support("base").reaction).tail<3>().norm(),
            1e-3 * reaction.tail<3>().norm());
}

TEST(LoadedLinkLoads, InternalForcesRunFromTheFromEndsWrenchToTheToEnds) {
  const Model m = bent_frame();
  const Result r = solve(m, loaded_options());
  for (std::size_t l = 0; l < m.links.size(); ++l) {
    const LinkResult& lr = r.links[l];
    if (!std::holds_alternative<BeamLink>(m.links[l].kind)) {
      EXPECT_TRUE(lr.internal_forces.empty());
      continue;
    }
    ASSERT_GE(lr.internal_forces.size(), 11u);
    const Vec6 first = lr.internal_forces.front().forces, last = lr.internal_forces.back().forces;
    ASSERT_EQ(lr.internal_forces.back().position, 1.0);
    const double scale = lr.from.wrench->norm() + lr.to.wrench->norm();
    // In the co-rotated axes (a rotation): −W_from at ξ = 0, W_to at ξ = 1.
    EXPECT_NEAR(first.head<3>().norm(), lr.from.wrench->head<3>().norm(), 1e-12 * scale);
    EXPECT_NEAR(first.tail<3>().norm(), lr.from.wrench->tail<3>().norm(), 1e-12 * scale);
    EXPECT_NEAR(last.head<3>().norm(), lr.to.wrench->head<3>().norm(), 1e-10 * scale);
    EXPECT_NEAR(last.tail<3>().norm(), lr.to.wrench->tail<3>().norm(), 1e-10 * scale);
    // One rotation E for both ends (first = −Eᵀ·W_from, last = Eᵀ·W_to) keeps every dot product
    // of the four vectors, with the signs of the two ends.
    const Vec3 f_from = lr.from.wrench->head<3>(), m_from = lr.from.wrench->tail<3>();
    const Vec3 f_to = lr.to.wrench->head<3>(), m_to = lr.to.wrench->tail<3>();
    EXPECT_NEAR(first.head<3>().dot(last.head<3>()), -f_from.dot(f_to), 1e-10 * scale * scale);
    EXPECT_NEAR(first.tail<3>().dot(last.tail<3>()), -m_from.dot(m_to), 1e-10 * scale * scale);
    EXPECT_NEAR(first.head<3>().dot(last.tail<3>()), -f_from.dot(m_to), 1e-10 * scale * scale);
    EXPECT_NEAR(first.head<3>().dot(first.tail<3>()), f_from.dot(m_from), 1e-10 * scale * scale);
    // The axial force N along the current chord: −W_from·e1 at ξ = 0.
    auto point_of = [&](const std::string& name) {
      for (const Point& p : m.points)
        if (p.name == name) return p.position;
      return Vec3(Vec3::Zero());
    };
    const Vec3 chord = point_of(m.links[l].to) + lr.to.deflection->head<3>() -
                       point_of(m.links[l].from) - lr.from.deflection->head<3>();
    EXPECT_NEAR(first[0], -lr.from.wrench->head<3>().dot(chord.normalized()), 1e-12 * scale);
  }
}

// CAD links (compliance and matrix links) refuse loads along them in the loaded mode as in the
// linear one: their stiffness says nothing of what lies between their ends.
TEST(LoadedLinkLoads, ACadLinkRefusesLoadsAlongItAsInTheLinearMode) {
  Model m;
  m.name = "compliance-cantilever";
  m.add_point("O", Vec3::Zero());
  m.add_point("E", Vec3(1, 0, 0));
  Vec6 diagonal;
  diagonal << 1e-8, 3e-3, 2e-3, 5e-3, 6e-3, 9e-3;
  m.add_compliance_link("arm", "O", "E", Mat6(diagonal.asDiagonal()));
  m.add_support("clamp", "O", {}, Connection::rigid());
  m.add_end_effector("tip", "E");
  m.add_link_load("arm", DistributedLinkLoad{Vec3(0, -40, 10), Vec3(5, -20, 30)});
  try {
    solve(m, loaded_options());
    FAIL() << "a load along a compliance link was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a compliance link"), std::string::npos) << e.what();
  }
}

// At the block, a link without a shape along its length (neither beam nor rigid) takes its
// loads by the lever rule on its chord, with couples at its `from` end, as the linear mode
// does for such a link (§13.2).
TEST(LoadedLinkLoads, ALinkWithoutAShapeTakesItsLoadsByTheLeverRule) {
  const Link link{"arm", "a", "b", ComplianceLink{Mat6::Identity(), LinkFrame::global, {}}, {}};
  const auto block =
      detail::with_loads_along(std::make_unique<NoRows>(), link, kFrom, kTo, some_loads());
  const auto [i, j] = deformed_ends();
  const VecX r = residual_of(*block, i, j);
  Vec12 expected = Vec12::Zero();  // minus the clamp wrenches
  const double length = (kTo - kFrom).norm();
  for (const LoadAlongLink& load : some_loads()) {
    if (const auto* q = std::get_if<DistributedLinkLoad>(&load)) {
      expected.segment<3>(0) += length * (2 * q->from + q->to) / 6;
      expected.segment<3>(6) += length * (q->from + 2 * q->to) / 6;
    } else {
      const auto& p = std::get<PointLinkLoad>(load);
      expected.segment<3>(0) += (1 - p.position) * p.force;
      expected.segment<3>(3) += p.moment;
      expected.segment<3>(6) += p.position * p.force;
    }
  }
  EXPECT_LT((r - expected).norm(), 1e-13 * expected.norm());
}

// ---- the command line -------------------------------------------------------------------------

int run_cli(const std::string& arguments, const std::string& output) {
  return testing::run_into(STIFFMSA_CLI, arguments, output);
}

TEST(LoadedLinkLoadsCli, ThePortalFramesLoadCasesAndWeightSolveInTheLoadedMode) {
  const auto dir = std::filesystem::temp_directory_path() / "stiffmsa-loaded-link-loads";
  std::filesystem::create_directories(dir);
  const std::string json = (dir / "portal.json").string();
  ASSERT_EQ(run_cli("solve " + std::string(STIFFMSA_SOURCE_DIR) +
                        "/examples/portal-frame-load-cases.yaml --loaded --json " + json,
                    (dir / "portal.txt").string()),
            0)
      << testing::read_file(dir / "portal.txt");
  const std::string text = testing::read_file(json);
  EXPECT_NE(text.find("\"mode\": \"loaded\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"weight\": {"), std::string::npos);
  EXPECT_NE(text.find("\"internal_forces\""), std::string::npos);
  EXPECT_NE(text.find("\"linear\": {"), std::string::npos);
}

}  // namespace
}  // namespace stiffmsa
