// Loads along a beam and its geometric stiffness (theory.md §12), against textbook closed forms,
// statics, an independent mesh of many elements, and Euler's and Engesser's critical loads.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include "elements/beam_element.hpp"
#include "elements/beam_geometric.hpp"
#include "elements/beam_loads.hpp"

using namespace stiffmsa;
using namespace stiffmsa::detail;

namespace {

constexpr double kClosedFormTolerance = 1e-12;    // relative, where only rounding separates them
constexpr double kMeshTolerance = 1e-12;          // a mesh that is exact but for rounding
constexpr double kExtrapolatedTolerance = 1e-10;  // Richardson: O(h⁴) and rounding, 400 elements
constexpr double kBucklingTolerance = 1e-6;       // the 1e-6, with enough elements

enum { u1 = 0, v1, w1, tx1, ty1, tz1, u2, v2, w2, tx2, ty2, tz2 };

constexpr double kLength = 1.7;

// A steel-like beam, Iy ≠ Iz so that the two planes cannot stand in for each other.
BeamConstants beam(double phi_y = 0, double phi_z = 0, double length = kLength) {
  BeamConstants c;
  c.length = length;
  c.E = 2.1e11;
  c.G = 8.1e10;
  c.A = 3.2e-3;
  c.Iy = 2.3e-6;
  c.Iz = 5.9e-6;
  c.J = 1.4e-6;
  c.phi_y = phi_y;
  c.phi_z = phi_z;
  return c;
}

// Forces compared to `force_scale`, moments to `force_scale`·length.
void expect_end_forces_near(const Vec12& actual, const Vec12& expected, double force_scale,
                            double tolerance) {
  for (int i = 0; i < 12; ++i) {
    const bool moment = (i % 6) >= 3;
    const double scale = moment ? force_scale * kLength : force_scale;
    EXPECT_NEAR(actual(i), expected(i), tolerance * scale) << "component " << i;
  }
}

// The resultant force and the resultant moment about the `from` end of the applied loads.
Vec6 applied_resultant(const BeamLoad& load, double L) {
  Vec6 r = Vec6::Zero();
  if (const auto* d = std::get_if<DistributedLoad>(&load)) {
    r.head<3>() = L * (d->q_from + d->q_to) / 2;
    // ∫₀ᴸ x·q(x) dx = L²(q_from + 2·q_to)/6, at lever arm along x
    r.tail<3>() = Vec3::UnitX().cross(L * L * (d->q_from + 2 * d->q_to) / 6);
  } else {
    const auto& p = std::get<PointLoad>(load);
    r.head<3>() = p.force;
    r.tail<3>() = p.moment + (p.position * L * Vec3::UnitX()).cross(p.force);
  }
  return r;
}

Vec6 end_forces_resultant(const Vec12& f, double L) {
  Vec6 r;
  r.head<3>() = f.segment<3>(0) + f.segment<3>(6);
  r.tail<3>() = f.segment<3>(3) + f.segment<3>(9) + (L * Vec3::UnitX()).cross(f.segment<3>(6));
  return r;
}

// --- An independent computation: the clamped beam as a mesh of `elements` beam elements ----
// Nodal loads are given per node (6 per node, local axes); returns the 12 reactions at the
// two clamped end nodes: (K·d − F) there.
Vec12 mesh_reactions(const BeamConstants& whole, int elements, const VecX& nodal_loads) {
  const int nodes = elements + 1, n = 6 * nodes;
  BeamConstants piece = whole;
  piece.length = whole.length / elements;
  const double ratio = double(elements) * elements;  // phi ∝ 1/L²
  piece.phi_y = whole.phi_y * ratio;
  piece.phi_z = whole.phi_z * ratio;
  const Mat12 k = beam_local_stiffness(piece);
  std::vector<Eigen::Triplet<double>> entries;
  for (int e = 0; e < elements; ++e)
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) entries.emplace_back(6 * e + i, 6 * e + j, k(i, j));
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(entries.begin(), entries.end());
  const int inner = n - 12;
  const Eigen::SparseMatrix<double> Kii = K.block(6, 6, inner, inner);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(Kii);
  VecX d = VecX::Zero(n);
  d.segment(6, inner) = solver.solve(nodal_loads.segment(6, inner));
  const VecX Kd = K * d;
  Vec12 reactions;
  reactions.head<6>() = Kd.head<6>() - nodal_loads.head<6>();
  reactions.tail<6>() = Kd.tail<6>() - nodal_loads.tail<6>();
  return reactions;
}

// The linear load's work-equivalent nodal forces with hat functions (no moments): exact statics,
// O(h²) in the reactions.
VecX hat_nodal_loads(const DistributedLoad& load, int elements) {
  VecX f = VecX::Zero(6 * (elements + 1));
  const double h = kLength / elements;
  auto q = [&](int node) {
    const double xi = double(node) / elements;
    return Vec3((1 - xi) * load.q_from + xi * load.q_to);
  };
  for (int e = 0; e < elements; ++e) {
    f.segment<3>(6 * e) += h * (2 * q(e) + q(e + 1)) / 6;
    f.segment<3>(6 * (e + 1)) += h * (q(e) + 2 * q(e + 1)) / 6;
  }
  return f;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Fixed-end forces against the textbook (Euler–Bernoulli; x-z plane by w' = −θy)

TEST(FixedEndForces, UniformLoadIsQlOverTwoAndQlSquaredOverTwelve) {
  const double L = kLength, qx = 310, qy = -1250, qz = 870;
  const Vec12 f = beam_fixed_end_forces(beam(), DistributedLoad::uniform(Vec3(qx, qy, qz)));
  Vec12 expected = Vec12::Zero();
  expected(u1) = expected(u2) = -qx * L / 2;
  expected(v1) = expected(v2) = -qy * L / 2;
  expected(w1) = expected(w2) = -qz * L / 2;
  expected(tz1) = -qy * L * L / 12;
  expected(tz2) = qy * L * L / 12;
  expected(ty1) = qz * L * L / 12;
  expected(ty2) = -qz * L * L / 12;
  expect_end_forces_near(f, expected, 1250 * L, kClosedFormTolerance);
}

TEST(FixedEndForces, ShearDeformationLeavesTheUniformLoadsForcesUnchanged) {
  // Symmetry: the end slopes of the symmetric load are zero whatever the shear flexibility.
  const auto load = DistributedLoad::uniform(Vec3(310, -1250, 870));
  expect_end_forces_near(beam_fixed_end_forces(beam(0.8, 2.5), load),
                         beam_fixed_end_forces(beam(), load), 1250 * kLength, kClosedFormTolerance);
}

TEST(FixedEndForces, TriangularLoadIsThreeAndSevenTwentiethsAndQlSquaredOverThirtyAndTwenty) {
  const double L = kLength, q = 2000;
  const Vec12 f = beam_fixed_end_forces(beam(), DistributedLoad{Vec3::Zero(), Vec3(q, q, q)});
  Vec12 expected = Vec12::Zero();
  expected(u1) = -q * L / 6;
  expected(u2) = -q * L / 3;
  expected(v1) = expected(w1) = -3 * q * L / 20;
  expected(v2) = expected(w2) = -7 * q * L / 20;
  expected(tz1) = -q * L * L / 30;
  expected(tz2) = q * L * L / 20;
  expected(ty1) = q * L * L / 30;
  expected(ty2) = -q * L * L / 20;
  expect_end_forces_near(f, expected, q * L, kClosedFormTolerance);
}

TEST(FixedEndForces, PointForceIsPabSquaredOverLSquared) {
  const double L = kLength, P = 4200, Fx = -900;
  for (double fraction : {0.0, 0.3, 0.5, 0.85, 1.0}) {
    const double a = fraction * L, b = L - a;
    const Vec12 f =
        beam_fixed_end_forces(beam(), PointLoad{Vec3(Fx, P, P), Vec3::Zero(), fraction});
    Vec12 expected = Vec12::Zero();
    expected(u1) = -Fx * b / L;
    expected(u2) = -Fx * a / L;
    expected(v1) = expected(w1) = -P * b * b * (L + 2 * a) / (L * L * L);
    expected(v2) = expected(w2) = -P * a * a * (L + 2 * b) / (L * L * L);
    expected(tz1) = -P * a * b * b / (L * L);
    expected(tz2) = P * a * a * b / (L * L);
    expected(ty1) = P * a * b * b / (L * L);
    expected(ty2) = -P * a * a * b / (L * L);
    expect_end_forces_near(f, expected, P, kClosedFormTolerance);
  }
}

TEST(FixedEndForces, PointMomentIsSixMabOverLCubedAndMbTwoAMinusBOverLSquared) {
  const double L = kLength, M = 730, Mx = 210;
  for (double fraction : {0.0, 0.3, 0.5, 0.85, 1.0}) {
    const double a = fraction * L, b = L - a;
    const Vec12 f =
        beam_fixed_end_forces(beam(), PointLoad{Vec3::Zero(), Vec3(Mx, M, M), fraction});
    Vec12 expected = Vec12::Zero();
    expected(tx1) = -Mx * b / L;
    expected(tx2) = -Mx * a / L;
    // About z: the x-y plane as printed. About y: w' = −θy turns the shears' signs only.
    expected(v1) = 6 * M * a * b / (L * L * L);
    expected(v2) = -expected(v1);
    expected(w1) = -expected(v1);
    expected(w2) = expected(v1);
    expected(tz1) = expected(ty1) = M * b * (2 * a - b) / (L * L);
    expected(tz2) = expected(ty2) = M * a * (2 * b - a) / (L * L);
    expect_end_forces_near(f, expected, M / L, kClosedFormTolerance);
  }
}

TEST(FixedEndForces, EveryLoadIsBalancedByItsEndForces) {
  const std::vector<BeamLoad> loads = {
      DistributedLoad::uniform(Vec3(310, -1250, 870)),
      DistributedLoad{Vec3(-400, 900, 1500), Vec3(250, -1300, 60)},
      PointLoad{Vec3(-900, 4200, -3100), Vec3(210, -730, 480), 0.0},
      PointLoad{Vec3(-900, 4200, -3100), Vec3(210, -730, 480), 0.37},
      PointLoad{Vec3(-900, 4200, -3100), Vec3(210, -730, 480), 1.0}};
  for (const BeamConstants& c : {beam(), beam(0.3, 1.7), beam(4.0, 0.05)})
    for (const BeamLoad& load : loads) {
      const Vec6 total = end_forces_resultant(beam_fixed_end_forces(c, load), kLength) +
                         applied_resultant(load, kLength);
      EXPECT_LT(total.head<3>().norm(), kClosedFormTolerance * 5000) << total.transpose();
      EXPECT_LT(total.tail<3>().norm(), kClosedFormTolerance * 5000 * kLength) << total.transpose();
    }
}

TEST(FixedEndForces, RefusesAPositionOutsideTheBeam) {
  for (double position : {-0.01, 1.01, std::nan("")}) {
    try {
      beam_fixed_end_forces(beam(), PointLoad{Vec3(0, 1, 0), Vec3::Zero(), position});
      ADD_FAILURE() << "position " << position << " accepted";
    } catch (const InputError& error) {
      ASSERT_EQ(error.diagnostics().size(), 1u);
      EXPECT_EQ(error.diagnostics()[0].key_path, "position");
      EXPECT_NE(error.diagnostics()[0].message.find("[0, 1]"), std::string::npos);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Timoshenko's fixed-end forces against a mesh of Timoshenko elements

TEST(TimoshenkoFixedEndForces, PointLoadsMatchAMeshWithANodeUnderTheLoad) {
  // An unloaded exact element is exact: with a node at the load, the mesh's reactions are the
  // beam's exact ones whatever the number of elements.
  for (const BeamConstants& c : {beam(0.6, 2.2), beam(3.0, 0.1)})
    for (int elements : {10, 40}) {
      const double fraction = 0.3;
      const PointLoad load{Vec3(-900, 4200, -3100), Vec3(210, -730, 480), fraction};
      VecX nodal = VecX::Zero(6 * (elements + 1));
      const int node = static_cast<int>(std::lround(fraction * elements));
      nodal.segment<3>(6 * node) = load.force;
      nodal.segment<3>(6 * node + 3) = load.moment;
      expect_end_forces_near(beam_fixed_end_forces(c, load), mesh_reactions(c, elements, nodal),
                             4200, kMeshTolerance);
    }
}

TEST(TimoshenkoFixedEndForces, DistributedLoadsAreTheLimitOfFinerMeshes) {
  const DistributedLoad load{Vec3(-400, 900, 1500), Vec3(250, -1300, 60)};
  for (const BeamConstants& c : {beam(0.6, 2.2), beam(3.0, 0.1)}) {
    const Vec12 exact = beam_fixed_end_forces(c, load);
    const double scale = 1500 * kLength;
    double previous_error = 0;
    Vec12 previous;
    for (int elements : {25, 50, 100, 200, 400}) {
      const Vec12 mesh = mesh_reactions(c, elements, hat_nodal_loads(load, elements));
      const double error = (mesh - exact).cwiseAbs().maxCoeff() / scale;
      if (previous_error > 0) {
        // O(h²): each halving of the elements divides the error by about four.
        EXPECT_GT(previous_error / error, 3.9) << elements << " elements";
        EXPECT_LT(previous_error / error, 4.1) << elements << " elements";
        const Vec12 richardson = (4 * mesh - previous) / 3;
        if (elements == 400) {
          std::printf("%d elements: error %.3e, extrapolated %.3e\n", elements, error,
                      (richardson - exact).cwiseAbs().maxCoeff() / scale);
          expect_end_forces_near(richardson, exact, scale, kExtrapolatedTolerance);
        }
      }
      previous_error = error;
      previous = mesh;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Internal forces at stations

TEST(InternalForces, ClampedBeamUnderAUniformLoad) {
  const double L = kLength, qx = 310, qy = -1250, qz = 870;
  const std::vector<BeamLoad> loads = {DistributedLoad::uniform(Vec3(qx, qy, qz))};
  const Vec12 f = beam_fixed_end_forces(beam(), loads[0]);
  for (double station : {0.0, 0.2, 0.5, 0.77, 1.0}) {
    const double x = station * L;
    const Vec6 s = beam_internal_forces(L, f.head<6>(), loads, station);
    Vec6 expected;
    expected << qx * (L / 2 - x), qy * (L / 2 - x), qz * (L / 2 - x), 0,
        -qz * (L * L / 12 - L * x / 2 + x * x / 2), qy * (L * L / 12 - L * x / 2 + x * x / 2);
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(s(i), expected(i), kClosedFormTolerance * 1250 * L * L) << station << " " << i;
  }
}

TEST(InternalForces, SimplySupportedBeamUnderAPointLoad) {
  const double L = kLength, P = 4200, T = 300, fraction = 0.35, a = fraction * L, b = L - a;
  // Simple supports: shear reactions only, torque held at the `from` end.
  Vec6 from_end;
  from_end << 0, -P * b / L, -P * b / L, -T, 0, 0;
  const std::vector<BeamLoad> loads = {PointLoad{Vec3(0, P, P), Vec3(T, 0, 0), fraction}};
  for (double station : {0.0, 0.1, 0.35, 0.6, 1.0}) {
    const double x = station * L;
    const bool before = station <= fraction;  // the load at its own station counts after it
    const Vec6 s = beam_internal_forces(L, from_end, loads, station);
    const double shear = before ? P * b / L : -P * a / L;
    const double sagging = before ? P * b * x / L : P * a * (L - x) / L;
    Vec6 expected;
    expected << 0, shear, shear, before ? T : 0, sagging, -sagging;
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(s(i), expected(i), kClosedFormTolerance * P * L) << station << " " << i;
  }
}

TEST(InternalForces, CantileverUnderALinearLoad) {
  const double L = kLength, q1 = 900, q2 = -1300;
  const std::vector<BeamLoad> loads = {DistributedLoad{Vec3(0, q1, 0), Vec3(0, q2, 0)}};
  // Clamped at `from`, free at `to`: the clamp balances the whole load.
  const Vec6 resultant = applied_resultant(loads[0], L);
  const Vec6 from_end = -resultant;
  const double k = (q2 - q1) / L;
  for (double station : {0.0, 0.25, 0.6, 1.0}) {
    const double x = station * L;
    const Vec6 s = beam_internal_forces(L, from_end, loads, station);
    // What lies beyond x: ∫ₓᴸ q ds and ∫ₓᴸ (s − x)·q ds.
    const double shear = q1 * (L - x) + k * (L * L - x * x) / 2;
    const double moment =
        q1 * (L - x) * (L - x) / 2 + k * ((L * L * L - x * x * x) / 3 - x * (L * L - x * x) / 2);
    EXPECT_NEAR(s(1), shear, kClosedFormTolerance * 1300 * L) << station;
    EXPECT_NEAR(s(5), moment, kClosedFormTolerance * 1300 * L * L) << station;
    EXPECT_NEAR(s(0), 0, kClosedFormTolerance * 1300 * L);
    EXPECT_NEAR(s(4), 0, kClosedFormTolerance * 1300 * L * L);
  }
}

TEST(InternalForces, RunFromMinusTheFromEndsForcesToTheToEndsForces) {
  // A loaded element's end forces k·d + fixed-end forces, for any d: balanced by construction.
  const BeamConstants c = beam(0.4, 1.1);
  const std::vector<BeamLoad> loads = {
      DistributedLoad{Vec3(-400, 900, 1500), Vec3(250, -1300, 60)},
      PointLoad{Vec3(-900, 4200, -3100), Vec3(210, -730, 480), 0.37}};
  Vec12 d;
  d << 1e-4, -2e-4, 3e-4, 1e-3, -2e-3, 5e-4, -1e-4, 4e-4, -2e-4, -1e-3, 3e-3, 2e-4;
  Vec12 f = beam_local_stiffness(c) * d;
  for (const BeamLoad& load : loads) f += beam_fixed_end_forces(c, load);
  const double scale = f.cwiseAbs().maxCoeff();
  const Vec6 at_from = beam_internal_forces(c.length, f.head<6>(), loads, 0.0);
  const Vec6 at_to = beam_internal_forces(c.length, f.head<6>(), loads, 1.0);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(at_from(i), -f(i), kClosedFormTolerance * scale) << i;
    EXPECT_NEAR(at_to(i), f(6 + i), kClosedFormTolerance * scale) << i;
  }
}

TEST(InternalForces, RefusesAStationOutsideTheBeam) {
  EXPECT_THROW(beam_internal_forces(kLength, Vec6::Zero(), {}, 1.5), InputError);
  EXPECT_THROW(beam_internal_forces(kLength, Vec6::Zero(), {}, -0.5), InputError);
}

// ---------------------------------------------------------------------------------------------
// Geometric stiffness and critical loads

TEST(GeometricStiffness, IsSymmetricLinearInTheForceAndBlindToTranslations) {
  const BeamConstants c = beam(0.7, 1.9);
  const Mat12 kg = beam_geometric_stiffness(c, -1234.5);
  EXPECT_EQ(kg, kg.transpose());
  EXPECT_LT((beam_geometric_stiffness(c, 2 * -1234.5) - 2 * kg).norm(), 1e-12 * kg.norm());
  for (int axis = 0; axis < 3; ++axis) {
    Vec12 translation = Vec12::Zero();
    translation(axis) = translation(6 + axis) = 1;
    EXPECT_LT((kg * translation).norm(), 1e-12 * kg.norm());
  }
}

namespace {

enum class Ends { pinned_pinned, clamped_free };

// The smallest compressive force P at which K − P·G is singular (G = −K_G at N = −1) for a
// column of `elements` equal elements along x: the largest μ of G·φ = μ·K·φ is 1/P.
double critical_load(const BeamConstants& whole, int elements, Ends ends) {
  const int n = 6 * (elements + 1);
  BeamConstants piece = whole;
  piece.length = whole.length / elements;
  piece.phi_y = whole.phi_y * elements * elements;
  piece.phi_z = whole.phi_z * elements * elements;
  const Mat12 k = beam_local_stiffness(piece), g = beam_geometric_stiffness(piece, -1.0);
  MatX K = MatX::Zero(n, n), G = MatX::Zero(n, n);
  for (int e = 0; e < elements; ++e) {
    K.block<12, 12>(6 * e, 6 * e) += k;
    G.block<12, 12>(6 * e, 6 * e) -= g;
  }
  std::vector<int> held;
  const int last = 6 * elements;
  if (ends == Ends::pinned_pinned)
    held = {u1, v1, w1, tx1, last + 1, last + 2};
  else
    held = {u1, v1, w1, tx1, ty1, tz1};
  std::vector<int> kept;
  for (int i = 0; i < n; ++i)
    if (std::find(held.begin(), held.end(), i) == held.end()) kept.push_back(i);
  const int m = static_cast<int>(kept.size());
  MatX Kr(m, m), Gr(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      Kr(i, j) = K(kept[i], kept[j]);
      Gr(i, j) = G(kept[i], kept[j]);
    }
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> solver(Gr, Kr);
  return 1 / solver.eigenvalues().maxCoeff();
}

// Below this the generalised eigensolver's rounding, not the mesh, sets the error (seen at
// about 2e-9 with 64 elements), so the order of convergence is not judged there.
constexpr double kEigenRoundingFloor = 1e-8;

// Relative errors for 1, 2, 4, … 64 elements, falling by about 2^order per halving while above
// rounding (at least 3/4 of it, from 4 elements), and within 1e-6 of `exact` from 32 elements —
// for second order, Richardson's extrapolation (2^order·P(2n) − P(n))/(2^order − 1) of 32 and 64.
void expect_converges(const BeamConstants& c, Ends ends, double exact, int order,
                      const char* what) {
  const double halving = std::pow(2.0, order);
  double previous_error = 0, previous_load = 0;
  for (int elements = 1; elements <= 64; elements *= 2) {
    const double load = critical_load(c, elements, ends);
    const double error = load / exact - 1;
    std::printf("%s: %2d elements, P/P_exact - 1 = %.3e\n", what, elements, error);
    EXPECT_GT(error, -1e-12) << "consistent elements approach from above";
    if (elements >= 4 && previous_error > kEigenRoundingFloor) {
      EXPECT_GT(previous_error / error, 0.75 * halving) << elements << " elements";
    }
    if (order >= 4 && elements >= 32) {
      EXPECT_LT(std::abs(error), kBucklingTolerance) << elements;
    }
    if (order < 4 && elements == 64) {
      const double extrapolated = (halving * load - previous_load) / (halving - 1);
      std::printf("%s: extrapolated from 32 and 64, P/P_exact - 1 = %.3e\n", what,
                  extrapolated / exact - 1);
      EXPECT_LT(std::abs(extrapolated / exact - 1), kBucklingTolerance);
    }
    previous_error = error;
    previous_load = load;
  }
}

}  // namespace

TEST(CriticalLoad, PinnedPinnedColumnConvergesToEulersPiSquaredEIOverLSquared) {
  const BeamConstants c = beam();
  const double pi2 = std::numbers::pi * std::numbers::pi;
  expect_converges(c, Ends::pinned_pinned, pi2 * c.E * c.Iy / (c.length * c.length), 4,
                   "pinned-pinned");
}

TEST(CriticalLoad, ClampedFreeColumnConvergesToEulersPiSquaredEIOverFourLSquared) {
  const BeamConstants c = beam();
  const double pi2 = std::numbers::pi * std::numbers::pi;
  expect_converges(c, Ends::clamped_free, pi2 * c.E * c.Iy / (4 * c.length * c.length), 4,
                   "clamped-free");
}

TEST(CriticalLoad, TimoshenkoColumnConvergesToEngessersLoad) {
  // P = P_E / (1 + P_E/(G·Asz)), with G·Asz = 12·E·Iy/(phi_z·L²); a shear-soft column.
  const double phi_z = 0.5, phi_y = 0.3;
  const BeamConstants c = beam(phi_y, phi_z);
  const double pi2 = std::numbers::pi * std::numbers::pi, L2 = c.length * c.length;
  const double euler = pi2 * c.E * c.Iy / L2;
  const double shear_stiffness = 12 * c.E * c.Iy / (phi_z * L2);
  // The shear-flexible elements converge at second order only: as elements shorten their phi
  // grows as 1/h², and their deflection tends to the linear one of a shear panel.
  expect_converges(c, Ends::pinned_pinned, euler / (1 + euler / shear_stiffness), 2,
                   "Timoshenko pinned-pinned");
}

TEST(CriticalLoad, TorsionalBucklingIsGJOverTheSquaredPolarRadiusOfGyration) {
  // Without warping stiffness every twist mode buckles at P = G·J·A/(Iy + Iz), whatever the mesh.
  BeamConstants c = beam();
  c.J = 1e-9;  // torsion far softer than bending, so that it is the smallest
  const double exact = c.G * c.J * c.A / (c.Iy + c.Iz);
  for (int elements : {1, 5})
    EXPECT_NEAR(critical_load(c, elements, Ends::clamped_free), exact,
                kClosedFormTolerance * 1e3 * exact);
}
