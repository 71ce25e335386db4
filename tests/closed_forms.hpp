#pragma once
// Independent reference formulas for the tests: textbook closed forms written without any
// code from the library, so a test compares the engine with something it did not compute.
#include <Eigen/Dense>
#include <cmath>

#include "stiffmsa/types.hpp"

namespace reference {

using stiffmsa::Mat3;
using stiffmsa::Mat6;
using stiffmsa::Vec3;
using stiffmsa::Vec6;

// Tip compliance of a cantilever (clamped at x = 0, tip at x = L) in its local axes, order
// [dx, dy, dz, rx, ry, rz]. Shear areas of 0 mean Euler–Bernoulli.
inline Mat6 cantilever_compliance(double L, double E, double G, double A, double Iy, double Iz,
                                  double J, double Asy = 0, double Asz = 0) {
  Mat6 c = Mat6::Zero();
  c(0, 0) = L / (E * A);
  c(1, 1) = L * L * L / (3 * E * Iz) + (Asy > 0 ? L / (G * Asy) : 0.0);
  c(2, 2) = L * L * L / (3 * E * Iy) + (Asz > 0 ? L / (G * Asz) : 0.0);
  c(3, 3) = L / (G * J);
  c(4, 4) = L / (E * Iy);
  c(5, 5) = L / (E * Iz);
  c(1, 5) = c(5, 1) = L * L / (2 * E * Iz);
  c(2, 4) = c(4, 2) = -L * L / (2 * E * Iy);
  return c;
}

inline Mat3 cross_matrix(const Vec3& v) {
  Mat3 s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// Twist transport: a rigid body's small motion at p becomes, at p + d,
// [Δp + Δφ × d; Δφ] = M(d)·[Δp; Δφ].
inline Mat6 twist_transport(const Vec3& d) {
  Mat6 m = Mat6::Identity();
  m.block<3, 3>(0, 3) = -cross_matrix(d);
  return m;
}

// Block-diagonal rotation of 6-vectors (R maps local coordinates to global ones).
inline Mat6 rotate6(const Mat3& R) {
  Mat6 m = Mat6::Zero();
  m.block<3, 3>(0, 0) = R;
  m.block<3, 3>(3, 3) = R;
  return m;
}

// Largest entrywise difference relative to the largest entry of the reference.
template <class A, class B>
double relative_difference(const A& actual, const B& expected) {
  const double scale = expected.cwiseAbs().maxCoeff();
  return (actual - expected).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1.0);
}

// For compliance-like matrices whose entries span units: each entry against sqrt(|e_ii e_jj|).
inline double relative_difference_scaled(const Mat6& actual, const Mat6& expected) {
  double worst = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double scale = std::sqrt(std::abs(expected(i, i) * expected(j, j)));
      const double diff = std::abs(actual(i, j) - expected(i, j));
      worst = std::max(worst, scale > 0 ? diff / scale : diff);
    }
  return worst;
}

}  // namespace reference
