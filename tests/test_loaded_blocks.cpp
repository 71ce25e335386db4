// The loaded mode's element blocks (docs/theory.md §15.2–15.5): each block's residual and its
// hand-written tangent against the same rows written here again, from the theory's equations,
// and differentiated by Eigen's forward-mode duals (nested for the co-rotational link, whose rows
// are a gradient), on random states with finite rotations, wrenches, preloads and a settlement.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unsupported/Eigen/AutoDiff>
#include <utility>
#include <vector>

#include "elements/beam_element.hpp"
#include "elements/free_directions.hpp"
#include "elements/loaded_blocks.hpp"
#include "elements/loaded_derivatives.hpp"
#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {
namespace {

// Agreement of the block with the reference: every tangent entry within this of the largest
// entry of its row, every residual within this of the residual's scale (its largest entry, or
// what the rounding of the state costs where that is larger: a stiff link's internal forces).
constexpr double kAgreement = 1e-12;

template <class T>
using V3 = Eigen::Matrix<T, 3, 1>;
template <class T>
using M3 = Eigen::Matrix<T, 3, 3>;
template <class T>
using V6 = Eigen::Matrix<T, 6, 1>;

// ---- the reference: rows as templates on the scalar, differentiated by duals -------------------

using Dyn = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using DynVec = Eigen::Matrix<Dyn, Eigen::Dynamic, 1>;

template <class T>
M3<T> cross_matrix(const V3<T>& v) {
  M3<T> s;
  s << T(0), -v(2), v(1), v(2), T(0), -v(0), -v(1), v(0), T(0);
  return s;
}

// log(A) = atan2(|s|, c)/|s|·s (§15.6); the states here keep every angle well away from 0.
template <class T>
V3<T> log_of(const M3<T>& a) {
  using std::atan2;
  using std::sqrt;
  const V3<T> s(T(0.5) * (a(2, 1) - a(1, 2)), T(0.5) * (a(0, 2) - a(2, 0)),
                T(0.5) * (a(1, 0) - a(0, 1)));
  const T c = T(0.5) * (a.trace() - T(1));
  const T sine = sqrt(s.squaredNorm());
  return s * (atan2(sine, c) / sine);
}

template <class T>
struct End {
  V3<T> x;
  M3<T> rotation;
  V6<T> wrench;
};

// The ends with the increments [δx; δθ; δW] of end k as variables 12k … 12k + 11, the rotation
// (I + [δθ×])·R (exp's first derivatives at δθ = 0).
std::vector<End<Dyn>> variable_ends(const std::vector<EndState>& states,
                                    const std::vector<int>& ends) {
  const int n = 12 * static_cast<int>(ends.size());
  std::vector<End<Dyn>> out;
  for (std::size_t k = 0; k < ends.size(); ++k) {
    const EndState& s = states[static_cast<std::size_t>(ends[k])];
    const int first = 12 * static_cast<int>(k);
    End<Dyn> e;
    V3<Dyn> turn;
    for (int i = 0; i < 3; ++i) {
      e.x(i) = Dyn(s.position(i), n, first + i);
      turn(i) = Dyn(0.0, n, first + 3 + i);
    }
    for (int i = 0; i < 6; ++i) e.wrench(i) = Dyn(s.wrench(i), n, first + 6 + i);
    const M3<Dyn> r = s.rotation.cast<Dyn>();
    e.rotation = r + cross_matrix(turn) * r;
    out.push_back(e);
  }
  return out;
}

struct Rows {
  VecX residual;
  MatX tangent;
};

template <class Equations>
Rows reference_rows(const std::vector<EndState>& states, const std::vector<int>& ends,
                    Equations&& equations) {
  const std::vector<End<Dyn>> e = variable_ends(states, ends);
  const std::vector<Dyn> r = equations(e);
  const Index n = 12 * static_cast<Index>(ends.size());
  Rows out{VecX(static_cast<Index>(r.size())), MatX::Zero(static_cast<Index>(r.size()), n)};
  for (std::size_t i = 0; i < r.size(); ++i) {
    out.residual(static_cast<Index>(i)) = r[i].value();
    if (r[i].derivatives().size() == n)
      out.tangent.row(static_cast<Index>(i)) = r[i].derivatives().transpose();
  }
  return out;
}

template <class T>
void append(std::vector<T>& rows, const Eigen::Matrix<T, Eigen::Dynamic, 1>& v) {
  for (Index i = 0; i < v.size(); ++i) rows.push_back(v(i));
}

Rows block_rows(const LoadedBlock& block, const LoadedInputs& in, double rounding_scale = 0) {
  Rows out{VecX(block.equation_count()), MatX()};
  block.evaluate(in, out.residual, &out.tangent);
  // Into a tangent the block wrote before, at another state, it writes the same: a block
  // writes only its pattern into a tangent of its size (LoadedBlock::evaluate).
  std::vector<EndState> moved = in.ends;
  for (EndState& e : moved) {
    e.position += Vec3(1e-3, -2e-3, 3e-3);
    e.rotation = Eigen::AngleAxisd(0.05, Vec3(0.6, 0.0, 0.8)) * e.rotation;
    e.wrench += Vec6::Constant(7.0);
  }
  MatX reused;
  VecX scratch(block.equation_count());
  block.evaluate(LoadedInputs{moved, in.external, 0.5 * in.load_factor + 0.25}, scratch, &reused);
  block.evaluate(in, scratch, &reused);
  EXPECT_TRUE(reused == out.tangent) << "a reused tangent differs";
  VecX alone(block.equation_count());
  block.evaluate(in, alone, nullptr);
  // The residual alone is the residual that comes with the tangent, to rounding.
  for (Index i = 0; i < alone.size(); ++i)
    EXPECT_NEAR(alone(i), out.residual(i),
                1e-13 * std::max(out.residual.cwiseAbs().maxCoeff(), rounding_scale))
        << "row " << i;
  return out;
}

void expect_agree(const Rows& block, const Rows& reference, double rounding_scale = 0) {
  ASSERT_EQ(block.residual.size(), reference.residual.size());
  ASSERT_EQ(block.tangent.rows(), reference.tangent.rows());
  ASSERT_EQ(block.tangent.cols(), reference.tangent.cols());
  const double residual_scale = std::max(reference.residual.cwiseAbs().maxCoeff(), rounding_scale);
  ASSERT_GT(residual_scale, 0);
  for (Index i = 0; i < reference.residual.size(); ++i) {
    EXPECT_NEAR(block.residual(i), reference.residual(i), kAgreement * residual_scale)
        << "residual row " << i;
    const double row_scale = reference.tangent.row(i).cwiseAbs().maxCoeff();
    ASSERT_GT(row_scale, 0) << "row " << i << " has no derivative";
    for (Index c = 0; c < reference.tangent.cols(); ++c)
      EXPECT_NEAR(block.tangent(i, c), reference.tangent(i, c), kAgreement * row_scale)
          << "tangent row " << i << ", column " << c;
  }
}

// ---- random states ---------------------------------------------------------------------------

class RandomStates {
 public:
  explicit RandomStates(unsigned seed) : engine_(seed) {}
  double uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(engine_);
  }
  Vec3 direction() {
    Vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    while (v.norm() < 0.2) v = Vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    return v.normalized();
  }
  // A rotation by 0.3 … 1 rad about a random axis.
  Mat3 rotation() { return Eigen::AngleAxisd(uniform(0.3, 1.0), direction()).toRotationMatrix(); }
  Vec6 wrench(double scale) {
    Vec6 w;
    for (int i = 0; i < 6; ++i) w(i) = scale * uniform(-1, 1);
    return w;
  }
  EndState end(const Vec3& around) {
    EndState s;
    s.position = around + 0.2 * direction();
    s.rotation = rotation();
    s.wrench = wrench(100);
    return s;
  }

 private:
  std::mt19937 engine_;
};

// ---- the co-rotational link (§15.2) ----------------------------------------------------------

// Its energy, written from §15.2, on nested duals: inner variables a (the virtual motion of the
// gradient), outer ones b (the Newton increment), R ← (I + [a_θ×])·(I + [b_θ×])·R.
using Outer = NestedDual;  // loaded_derivatives.hpp's seeding, inner a and outer b

template <class T>
T link_energy(const CorotationalLink& link, const V3<T>& xi, const M3<T>& ri, const V3<T>& xj,
              const M3<T>& rj) {
  const double length0 = link.d0.norm();
  const Vec3 n0 = link.d0 / length0;
  // r0: the global axis least aligned with n0, made orthogonal to it.
  Index least = 0;
  n0.cwiseAbs().minCoeff(&least);
  const Vec3 r0 = (Vec3::Unit(least) - n0(least) * n0).normalized();
  Mat3 frame0;
  frame0 << n0, r0, n0.cross(r0);
  const V3<T> chord = xj - xi;
  const T l = chord.norm();
  const V3<T> e1 = chord / l;
  const V3<T> q = T(0.5) * ((ri + rj) * r0.cast<T>());
  V3<T> e3 = e1.cross(q);
  e3 = e3 / e3.norm();
  M3<T> e;
  e << e1, e3.cross(e1), e3;
  const M3<T> rigid = e * frame0.transpose().cast<T>();
  Eigen::Matrix<T, 12, 1> d;
  d.template head<3>().setZero();
  d.template segment<3>(3) = log_of<T>(rigid.transpose() * ri);
  d.template segment<3>(6) = rigid.transpose() * chord - link.d0.cast<T>();
  d.template segment<3>(9) = log_of<T>(rigid.transpose() * rj);
  T energy = T(0.5) * d.dot(link.stiffness.cast<T>() * d);
  if (link.axial) {
    const V3<T> axis = n0.cast<T>();
    const V3<T> ti = d.template segment<3>(3) - axis * axis.dot(d.template segment<3>(3));
    const V3<T> tj = d.template segment<3>(9) - axis * axis.dot(d.template segment<3>(9));
    const T u = l - T(length0);
    const T stretch =
        u + T(length0 / 30) * (T(2) * ti.squaredNorm() - ti.dot(tj) + T(2) * tj.squaredNorm());
    energy += T(0.5 * *link.axial / length0) * (stretch * stretch - u * u);
  }
  return energy;
}

Rows corotational_reference(const CorotationalLink& link, const EndState& i, const EndState& j) {
  V3<Outer> xi, xj;
  M3<Outer> ri, rj;
  nested_moved_pose(i, 0, xi, ri);
  nested_moved_pose(j, 6, xj, rj);
  const Outer energy = link_energy<Outer>(link, xi, ri, xj, rj);
  Rows out{VecX(12), MatX::Zero(12, 24)};
  for (int m = 0; m < 12; ++m) {
    const int column = m < 6 ? m : m + 6;  // the t columns of the ends' [t, W]
    out.residual(m) = (m < 6 ? i.wrench(m) : j.wrench(m - 6)) - energy.value().derivatives()(m);
    for (int b = 0; b < 12; ++b)
      out.tangent(m, b < 6 ? b : b + 6) = -energy.derivatives()(b).derivatives()(m);
    out.tangent(m, column + 6) = 1;  // ∂W/∂W
  }
  return out;
}

// A link of length ~1 whose stiffness has entries of order 1 in every coupling, so that the
// geometric terms (the energy's gradient times d̄'s second derivatives) weigh as much in the
// tangent as K does.
CorotationalLink random_link(RandomStates& random, bool beam) {
  CorotationalLink link;
  link.d0 = random.direction() * random.uniform(0.7, 1.3);
  Eigen::Matrix<double, 12, 12> b;
  for (Index r = 0; r < 12; ++r)
    for (Index c = 0; c < 12; ++c) b(r, c) = random.uniform(-1, 1);
  link.stiffness = b.transpose() * b;
  if (beam) link.axial = random.uniform(20, 50);
  return link;
}

TEST(CorotationalLinkBlock, ResidualAndTangentMatchNestedDualsOnRandomStates) {
  RandomStates random(7);
  for (int trial = 0; trial < 12; ++trial) {
    const CorotationalLink link = random_link(random, trial % 2 == 0);
    std::vector<EndState> states(3);
    states[1] = random.end(Vec3(1, 2, 3));
    states[2] = random.end(states[1].position + link.d0);
    const auto block = make_corotational_link(1, 2, link);
    const std::vector<Vec6> external(3, Vec6::Zero());
    const Rows got = block_rows(*block, LoadedInputs{states, external, 0.8});
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_agree(got, corotational_reference(link, states[1], states[2]));
  }
}

// Small deformations (the rotation vectors of d̄ below 0.1 rad, where the inverse Jacobian's
// coefficient is its series) on top of a large rigid motion.
TEST(CorotationalLinkBlock, SmallDeformationsUnderALargeRigidMotionMatchNestedDuals) {
  RandomStates random(11);
  for (int trial = 0; trial < 8; ++trial) {
    const CorotationalLink link = random_link(random, trial % 2 == 1);
    const Mat3 turn = random.rotation();
    const Vec3 shift = random.direction();
    const double size = trial < 4 ? 0.05 : 2e-3;
    std::vector<EndState> states(2);
    states[0].position = shift + size * random.direction();
    states[0].rotation = Eigen::AngleAxisd(size, random.direction()) * turn;
    states[1].position = shift + turn * link.d0 + size * random.direction();
    states[1].rotation = Eigen::AngleAxisd(size, random.direction()) * turn;
    states[0].wrench = random.wrench(1);
    states[1].wrench = random.wrench(1);
    const auto block = make_corotational_link(0, 1, link);
    const std::vector<Vec6> external(2, Vec6::Zero());
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_agree(block_rows(*block, LoadedInputs{states, external, 1.0}),
                 corotational_reference(link, states[0], states[1]));
  }
}

// A beam of modulus E, Poisson's ratio ν and `section` from `from` to `to`, as the loaded mode
// builds its co-rotational link.
CorotationalLink beam_link(double e, double nu, const Section& section, const Vec3& from,
                           const Vec3& to) {
  BeamLink beam;
  beam.material.E = e;
  beam.material.nu = nu;
  beam.section = section;
  CorotationalLink link;
  link.d0 = to - from;
  link.stiffness = beam_global_stiffness(beam, from, to);
  link.axial = e * section_properties(section).A;
  return link;
}

// A real beam (steel tube), whose stiffness spans five orders between its axial and torsional
// terms: the tangent agrees row by row as above; the residual, the difference of internal forces
// of size E·A·u, to what positions' rounding costs, |K|·L.
TEST(CorotationalLinkBlock, SteelTubeMatchesNestedDuals) {
  RandomStates random(3);
  const Vec3 from(0.2, -0.1, 0.5), to(0.9, 0.4, 1.1);
  const CorotationalLink link = beam_link(2.1e11, 0.3, Section::tube(0.08, 0.005), from, to);
  for (int trial = 0; trial < 4; ++trial) {
    const Mat3 turn = random.rotation();
    std::vector<EndState> states(2);
    states[0].position = from + 1e-3 * random.direction();
    states[0].rotation = Eigen::AngleAxisd(0.02, random.direction()) * turn;
    states[1].position = from + turn * link.d0 + 1e-3 * random.direction();
    states[1].rotation = Eigen::AngleAxisd(0.02, random.direction()) * turn;
    const auto block = make_corotational_link(0, 1, link);
    const std::vector<Vec6> external(2, Vec6::Zero());
    SCOPED_TRACE("trial " + std::to_string(trial));
    const double rounding_scale = link.stiffness.cwiseAbs().maxCoeff() * link.d0.norm();
    expect_agree(block_rows(*block, LoadedInputs{states, external, 1.0}, rounding_scale),
                 corotational_reference(link, states[0], states[1]), rounding_scale);
  }
}

// Unloaded, and moved rigidly from there (d̄ = 0 exactly: the rotation vectors' and the inverse
// Jacobian's series at zero), the link holds no wrench and its tangent is the linear stiffness
// form of §3.3 turned with it, −T·K·Tᵀ (T = diag(Q, Q, Q, Q)): K holds the rigid motions in its
// null space, so that the frame's part of d̄ drops out and the geometric terms vanish with f.
TEST(CorotationalLinkBlock, RigidlyMovedLinkHasTheTurnedLinearStiffness) {
  RandomStates random(5);
  const Vec3 from(0.3, 0.1, -0.2), to(-0.4, 0.6, 0.5);
  const CorotationalLink link = beam_link(7e10, 0.33, Section::rect(0.04, 0.07), from, to);
  for (int trial = 0; trial < 3; ++trial) {
    const Mat3 turn = trial == 0 ? Mat3::Identity() : random.rotation();
    const Vec3 shift = trial == 0 ? Vec3::Zero() : random.direction();
    std::vector<EndState> states(2);
    states[0].position = turn * from + shift;
    states[1].position = turn * to + shift;
    states[0].rotation = states[1].rotation = turn;
    states[0].wrench = random.wrench(100);
    states[1].wrench = random.wrench(100);
    const auto block = make_corotational_link(0, 1, link);
    const std::vector<Vec6> external(2, Vec6::Zero());
    const Rows got = block_rows(*block, LoadedInputs{states, external, 1.0});
    Mat12 rotate = Mat12::Zero();
    for (int b = 0; b < 4; ++b) rotate.block<3, 3>(3 * b, 3 * b) = turn;
    const Mat12 expected = -rotate * link.stiffness * rotate.transpose();
    const double scale = link.stiffness.cwiseAbs().maxCoeff();
    SCOPED_TRACE("trial " + std::to_string(trial));
    for (Index m = 0; m < 12; ++m) {
      const double wrench = m < 6 ? states[0].wrench(m) : states[1].wrench(m - 6);
      EXPECT_NEAR(got.residual(m), wrench, 1e-13 * scale * link.d0.norm()) << "row " << m;
      for (Index b = 0; b < 12; ++b)
        EXPECT_NEAR(got.tangent(m, b < 6 ? b : b + 6), expected(m, b), 1e-12 * scale)
            << "row " << m << ", column " << b;
    }
  }
}

// ---- joints, supports, rigid links and free ends (§15.3–15.5) --------------------------------

// [R_1ᵀ·(x_k − x_1); log(R_1ᵀ·R_k)]: end k's motion relative to end 1, in end 1's axes.
template <class T>
V6<T> motion_of(const End<T>& first, const End<T>& other) {
  V6<T> q;
  q << first.rotation.transpose() * (other.x - first.x),
      log_of<T>(first.rotation.transpose() * other.rotation);
  return q;
}

// W − W_ext of `end` about the point `about`, in the axes `axes`.
template <class T>
V6<T> wrench_about(const End<T>& end, const Vec6& external, const V3<T>& about, const M3<T>& axes) {
  const V3<T> force = end.wrench.template head<3>() - external.head<3>().cast<T>();
  const V3<T> moment =
      end.wrench.template tail<3>() - external.tail<3>().cast<T>() + (end.x - about).cross(force);
  V6<T> w;
  w << axes.transpose() * force, axes.transpose() * moment;
  return w;
}

struct Case {
  std::vector<EndState> states;
  std::vector<Vec6> external;
  double load_factor = 0.7;
};

// Five link ends, randomly placed and turned, with random wrenches and external loads.
Case random_case(RandomStates& random) {
  Case c;
  for (int e = 0; e < 5; ++e) {
    c.states.push_back(random.end(Vec3(0.5, -0.3, 1.0)));
    c.external.push_back(random.wrench(60));
  }
  return c;
}

Rows constraint_joint_reference(const Case& c, const std::vector<int>& ends,
                                const FreeDirections& directions,
                                const std::optional<VecX>& preload) {
  return reference_rows(c.states, ends, [&](const std::vector<End<Dyn>>& e) {
    const Index p = directions.p;
    const Eigen::Matrix<Dyn, Eigen::Dynamic, 6> free = directions.free().cast<Dyn>();
    const Eigen::Matrix<Dyn, Eigen::Dynamic, 6> held = directions.constrained().cast<Dyn>();
    std::vector<Dyn> rows;
    for (std::size_t k = 1; k < e.size(); ++k)
      append<Dyn>(rows, DynVec(-(held * motion_of(e[0], e[k]))));
    V6<Dyn> sum = V6<Dyn>::Zero();
    std::vector<V6<Dyn>> w;
    for (std::size_t k = 0; k < e.size(); ++k) {
      w.push_back(
          wrench_about(e[k], c.external[static_cast<std::size_t>(ends[k])], e[0].x, e[0].rotation));
      sum += w.back();
    }
    append<Dyn>(rows, DynVec(held * sum));
    for (std::size_t k = 0; k < e.size(); ++k) {
      DynVec rows_k = free * w[k];
      if (preload && k < 2) {
        const VecX g_w0 = directions.free() * directions.free().transpose() * *preload;
        for (Index i = 0; i < p; ++i)
          rows_k(i) += (k == 0 ? -c.load_factor : c.load_factor) * g_w0(i);
      }
      append<Dyn>(rows, rows_k);
    }
    return rows;
  });
}

Rows elastic_joint_reference(const Case& c, const std::vector<int>& ends,
                             const FreeDirections& directions, const MatX& stiffness,
                             const std::optional<VecX>& preload) {
  return reference_rows(c.states, ends, [&](const std::vector<End<Dyn>>& e) {
    const Index p = directions.p;
    const MatX gram = directions.free() * directions.free().transpose();
    const Eigen::Matrix<Dyn, Eigen::Dynamic, 6> free = directions.free().cast<Dyn>();
    const Eigen::Matrix<Dyn, Eigen::Dynamic, 6> held = directions.constrained().cast<Dyn>();
    const MatX spring = gram * stiffness * directions.free();
    const M3<Dyn> global = M3<Dyn>::Identity();
    std::vector<Dyn> rows;
    append<Dyn>(
        rows,
        DynVec(wrench_about(e[0], c.external[static_cast<std::size_t>(ends[0])], e[0].x, global) +
               wrench_about(e[1], c.external[static_cast<std::size_t>(ends[1])], e[0].x, global)));
    const V6<Dyn> q = motion_of(e[0], e[1]);
    append<Dyn>(rows, DynVec(-(held * q)));
    DynVec spring_rows = free * wrench_about(e[0], c.external[static_cast<std::size_t>(ends[0])],
                                             e[0].x, e[0].rotation) -
                         spring.cast<Dyn>() * q;
    if (preload) {
      const VecX g_w0 = gram * *preload;
      for (Index i = 0; i < p; ++i) spring_rows(i) -= c.load_factor * g_w0(i);
    }
    append<Dyn>(rows, spring_rows);
    return rows;
  });
}

Rows support_reference(const Case& c, const std::vector<int>& ends,
                       const FreeDirections& directions, const std::optional<MatX>& stiffness,
                       const std::optional<VecX>& preload, const Vec6& settlement,
                       const Vec3& unloaded_position) {
  return reference_rows(c.states, ends, [&](const std::vector<End<Dyn>>& e) {
    const Index p = directions.p;
    const MatX gram = directions.free() * directions.free().transpose();
    const Eigen::Matrix<Dyn, Eigen::Dynamic, 6> free = directions.free().cast<Dyn>();
    const Eigen::Matrix<Dyn, Eigen::Dynamic, 6> held = directions.constrained().cast<Dyn>();
    const Vec3 turn = c.load_factor * settlement.tail<3>();
    const M3<Dyn> ground =
        Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix().cast<Dyn>();
    const V3<Dyn> ground_point =
        (unloaded_position + c.load_factor * settlement.head<3>()).cast<Dyn>();
    std::vector<Dyn> rows;
    for (std::size_t k = 1; k < e.size(); ++k) {
      append<Dyn>(rows, DynVec(e[0].x - e[k].x));
      append<Dyn>(rows, DynVec(log_of<Dyn>(e[0].rotation * e[k].rotation.transpose())));
    }
    V6<Dyn> g;
    g << ground.transpose() * (e[0].x - ground_point),
        log_of<Dyn>(ground.transpose() * e[0].rotation);
    append<Dyn>(rows, DynVec(held * g));
    if (p == 0) return rows;
    V6<Dyn> sum = V6<Dyn>::Zero();
    for (std::size_t k = 0; k < e.size(); ++k)
      sum += wrench_about(e[k], c.external[static_cast<std::size_t>(ends[k])], e[0].x, ground);
    DynVec free_rows = free * sum;
    if (stiffness) free_rows += (gram * *stiffness * directions.free()).cast<Dyn>() * g;
    if (preload) {
      const VecX g_w0 = gram * *preload;
      for (Index i = 0; i < p; ++i) free_rows(i) -= c.load_factor * g_w0(i);
    }
    append<Dyn>(rows, free_rows);
    return rows;
  });
}

Rows rigid_link_reference(const Case& c, const std::vector<int>& ends, const Vec3& d0) {
  return reference_rows(c.states, ends, [&](const std::vector<End<Dyn>>& e) {
    const End<Dyn>& i = e[0];
    const End<Dyn>& j = e[1];
    std::vector<Dyn> rows;
    append<Dyn>(rows, DynVec(i.x + i.rotation * d0.cast<Dyn>() - j.x));
    append<Dyn>(rows, DynVec(log_of<Dyn>(i.rotation * j.rotation.transpose())));
    const V3<Dyn> force_j = j.wrench.head<3>();
    append<Dyn>(rows, DynVec(i.wrench.head<3>() + force_j));
    append<Dyn>(rows, DynVec(i.wrench.tail<3>() + j.wrench.tail<3>() + (j.x - i.x).cross(force_j)));
    return rows;
  });
}

// Free directions of every built-in kind and a custom joint whose rows are neither unit nor
// orthogonal (its Gram matrix is not the identity).
std::vector<std::pair<std::string, FreeDirections>> direction_kinds(RandomStates& random) {
  Vec6 a, b;
  a << 0.3, -0.2, 0.9, 1.4, 0.1, -0.5;
  b << -0.7, 0.4, 0.2, 0.3, 2.0, 0.6;
  return {
      {"rigid", FreeDirections{}},
      {"revolute", free_directions(Kinematics::revolute(random.direction()))},
      {"prismatic", free_directions(Kinematics::prismatic(random.direction()))},
      {"cylindrical", free_directions(Kinematics::cylindrical(random.direction()))},
      {"universal", free_directions(Kinematics::universal(random.direction(), random.direction()))},
      {"spherical", free_directions(Kinematics::spherical())},
      {"planar", free_directions(Kinematics::planar(random.direction()))},
      {"custom", free_directions(Kinematics::custom({a, b}))}};
}

VecX random_vector(RandomStates& random, Index size, double scale) {
  VecX v(size);
  for (Index i = 0; i < size; ++i) v(i) = scale * random.uniform(-1, 1);
  return v;
}

// A symmetric positive definite p×p spring.
MatX random_spring(RandomStates& random, Index p) {
  MatX b(p, p);
  for (Index r = 0; r < p; ++r)
    for (Index c = 0; c < p; ++c) b(r, c) = random.uniform(-1, 1);
  return 1e3 * (b.transpose() * b + MatX::Identity(p, p));
}

TEST(LoadedConstraintJointBlock, MatchesDualsForEveryKindAndTwoOrThreeEnds) {
  RandomStates random(21);
  for (int trial = 0; trial < 3; ++trial) {
    for (const auto& [name, directions] : direction_kinds(random)) {
      const Case c = random_case(random);
      for (const std::vector<int>& ends : {std::vector<int>{3, 1}, std::vector<int>{2, 4, 0}}) {
        const std::optional<VecX> preload =
            directions.p > 0 ? std::optional<VecX>(random_vector(random, directions.p, 40))
                             : std::nullopt;
        const auto block = make_loaded_constraint_joint(ends, directions, preload);
        SCOPED_TRACE(name + ", " + std::to_string(ends.size()) + " ends, trial " +
                     std::to_string(trial));
        expect_agree(block_rows(*block, LoadedInputs{c.states, c.external, c.load_factor}),
                     constraint_joint_reference(c, ends, directions, preload));
      }
    }
  }
}

TEST(LoadedElasticJointBlock, MatchesDualsForEveryKindWithPreloads) {
  RandomStates random(22);
  for (int trial = 0; trial < 3; ++trial) {
    for (const auto& [name, directions] : direction_kinds(random)) {
      if (directions.p == 0) continue;  // a spring needs a free direction
      const Case c = random_case(random);
      const std::vector<int> ends{4, 2};
      const MatX stiffness = random_spring(random, directions.p);
      const std::optional<VecX> preload =
          trial == 0 ? std::nullopt : std::optional<VecX>(random_vector(random, directions.p, 40));
      const auto block =
          make_loaded_elastic_joint(ends[0], ends[1], directions, stiffness, preload);
      SCOPED_TRACE(name + ", trial " + std::to_string(trial));
      expect_agree(block_rows(*block, LoadedInputs{c.states, c.external, c.load_factor}),
                   elastic_joint_reference(c, ends, directions, stiffness, preload));
    }
  }
}

TEST(LoadedSupportBlock, MatchesDualsWithSpringsPreloadsAndSettlements) {
  RandomStates random(23);
  for (int trial = 0; trial < 2; ++trial) {
    for (const auto& [name, directions] : direction_kinds(random)) {
      const Case c = random_case(random);
      const Vec3 unloaded_position = c.states[1].position + 0.01 * random.direction();
      Vec6 settlement;
      settlement << 0.02 * random.direction(), 0.3 * random.direction();
      for (const std::vector<int>& ends : {std::vector<int>{1}, std::vector<int>{1, 3, 0}}) {
        const bool spring = directions.p > 0 && ends.size() == 1;
        const std::optional<MatX> stiffness =
            spring ? std::optional<MatX>(random_spring(random, directions.p)) : std::nullopt;
        const std::optional<VecX> preload =
            directions.p > 0 ? std::optional<VecX>(random_vector(random, directions.p, 40))
                             : std::nullopt;
        const auto block = make_loaded_support(ends, directions, stiffness, preload, settlement,
                                               unloaded_position);
        SCOPED_TRACE(name + ", " + std::to_string(ends.size()) + " ends, trial " +
                     std::to_string(trial));
        expect_agree(block_rows(*block, LoadedInputs{c.states, c.external, c.load_factor}),
                     support_reference(c, ends, directions, stiffness, preload, settlement,
                                       unloaded_position));
      }
    }
  }
}

TEST(LoadedRigidLinkBlock, MatchesDualsOnRandomStates) {
  RandomStates random(24);
  for (int trial = 0; trial < 6; ++trial) {
    const Case c = random_case(random);
    const Vec3 d0 = random.direction() * random.uniform(0.2, 1.5);
    const std::vector<int> ends{trial % 5, (trial + 2) % 5};
    const auto block = make_loaded_rigid_link(ends[0], ends[1], d0);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_agree(block_rows(*block, LoadedInputs{c.states, c.external, c.load_factor}),
                 rigid_link_reference(c, ends, d0));
  }
}

// A rigid link carrying loads along it (a load varying linearly along it, point forces and a
// point moment), at points x_i + ξ·R_i·d0 that ride with it: the resultant enters the force
// balance, its moment about x_i the moment balance. The loads add to the δθ_i columns of the
// moment balance, which the rigid link zeroes at every evaluation: block_rows checks that a
// tangent kept from another state comes out the same.
TEST(LoadedRigidLinkBlock, WithLoadsAlongItMatchesDualsAndKeepsItsTangent) {
  RandomStates random(26);
  for (int trial = 0; trial < 4; ++trial) {
    const Case c = random_case(random);
    const Vec3 from = random.direction() * random.uniform(0.0, 2.0);
    const Vec3 d0 = random.direction() * random.uniform(0.2, 1.5);
    const std::vector<int> ends{trial % 5, (trial + 3) % 5};
    const Vec3 q_from = 300 * random.direction(), q_to = 500 * random.direction();
    const PointLinkLoad point{80 * random.direction(), 25 * random.direction(),
                              random.uniform(0.0, 1.0)};
    const PointLinkLoad force_only{60 * random.direction(), Vec3::Zero(), random.uniform(0, 1)};
    const std::vector<LoadAlongLink> loads{DistributedLinkLoad{q_from, q_to}, point, force_only};
    const Link link{"rigid", "a", "b", RigidLink{}, {}};
    const auto block = with_loads_along(make_loaded_rigid_link(ends[0], ends[1], d0), link, from,
                                        from + d0, loads);
    const double lambda = c.load_factor;
    const double length = d0.norm();
    const Rows expected = reference_rows(c.states, ends, [&](const std::vector<End<Dyn>>& e) {
      const End<Dyn>& i = e[0];
      const End<Dyn>& j = e[1];
      const V3<Dyn> arm = i.rotation * d0.cast<Dyn>();
      // q(ξ) = (1 − ξ)·q_from + ξ·q_to per unit length: resultant L·(q_from + q_to)/2, moment
      // about x_i ∫ ξ·arm × q(ξ)·L dξ = L·arm × (q_from/6 + q_to/3).
      const V3<Dyn> resultant =
          (length * (q_from + q_to) / 2 + point.force + force_only.force).cast<Dyn>();
      const V3<Dyn> moment = arm.cross((length * (q_from / 6 + q_to / 3)).cast<Dyn>()) +
                             (point.position * arm).cross(point.force.cast<Dyn>()) +
                             (force_only.position * arm).cross(force_only.force.cast<Dyn>()) +
                             point.moment.cast<Dyn>();
      std::vector<Dyn> rows;
      append<Dyn>(rows, DynVec(i.x + arm - j.x));
      append<Dyn>(rows, DynVec(log_of<Dyn>(i.rotation * j.rotation.transpose())));
      const V3<Dyn> force_j = j.wrench.head<3>();
      append<Dyn>(rows, DynVec(i.wrench.head<3>() + force_j + Dyn(lambda) * resultant));
      append<Dyn>(rows, DynVec(i.wrench.tail<3>() + j.wrench.tail<3>() +
                               (j.x - i.x).cross(force_j) + Dyn(lambda) * moment));
      return rows;
    });
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_agree(block_rows(*block, LoadedInputs{c.states, c.external, lambda}), expected);
  }
}

TEST(LoadedFreeEndBlock, IsTheWrenchLessTheLoad) {
  RandomStates random(25);
  const Case c = random_case(random);
  const auto block = make_loaded_free_end(3);
  const Rows got = block_rows(*block, LoadedInputs{c.states, c.external, c.load_factor});
  const Rows expected = reference_rows(c.states, {3}, [&](const std::vector<End<Dyn>>& e) {
    std::vector<Dyn> rows;
    append<Dyn>(rows, DynVec(e[0].wrench - c.external[3].cast<Dyn>()));
    return rows;
  });
  expect_agree(got, expected);
}

}  // namespace
}  // namespace stiffmsa::detail
