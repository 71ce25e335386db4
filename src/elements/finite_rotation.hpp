#pragma once
// Finite rotations for the loaded mode (docs/theory.md §15.6): the rotation vector of a rotation
// matrix (its logarithm), Rodrigues' formula, and the rotation vector's derivative (the inverse
// left Jacobian) that the loaded blocks' tangents are written with. The templates on the scalar
// also take Eigen's forward-mode duals: the load stiffness of loads along links is taken with
// them (loaded_link_loads.cpp, §15.9).
#include <Eigen/Core>
#include <cmath>
#include <unsupported/Eigen/AutoDiff>

#include "stiffmsa/types.hpp"

namespace stiffmsa::detail {

template <class T>
using Vec3T = Eigen::Matrix<T, 3, 1>;
template <class T>
using Mat3T = Eigen::Matrix<T, 3, 3>;

inline double value_of(double x) { return x; }
template <class D>
double value_of(const Eigen::AutoDiffScalar<D>& x) {
  return value_of(x.value());
}

template <class T>
Mat3T<T> skew_of(const Vec3T<T>& v) {
  Mat3T<T> s;
  s << T(0), -v.z(), v.y(), v.z(), T(0), -v.x(), -v.y(), v.x(), T(0);
  return s;
}

// The rotation vector φ of a rotation matrix A, A = exp([φ×]), |φ| < π. With s = axial(A) =
// sin|φ|·φ/|φ| and c = (tr A − 1)/2 = cos|φ|: φ = atan2(|s|, c)/|s|·s; near φ = 0, where |s|
// has no derivative, the series θ/sin θ = 1 + x/6 + 3x²/40 + O(x³), x = |s|² = sin²θ.
template <class T>
Vec3T<T> rotation_vector(const Mat3T<T>& a) {
  const Vec3T<T> s(T(0.5) * (a(2, 1) - a(1, 2)), T(0.5) * (a(0, 2) - a(2, 0)),
                   T(0.5) * (a(1, 0) - a(0, 1)));
  const T c = T(0.5) * (a(0, 0) + a(1, 1) + a(2, 2) - T(1));
  const T x = s.squaredNorm();
  constexpr double kSeriesBelow = 1e-8;  // x³ ≤ 1e-24: the series is exact in double
  if (value_of(x) < kSeriesBelow && value_of(c) > 0)
    return s * (T(1) + x / T(6) + T(3.0 / 40.0) * x * x);
  using std::atan2;
  using std::sqrt;
  const T sine = sqrt(x);
  return s * (atan2(sine, c) / sine);
}

// β(ϑ) = 1/ϑ² − (1 + cos ϑ)/(2·ϑ·sin ϑ) of the inverse left Jacobian below, from ϑ² = |φ|²;
// below ϑ = 0.1, where the difference cancels, its series 1/12 + ϑ²/720 + ϑ⁴/30240 +
// ϑ⁶/1209600 + ϑ⁸/47900160 (the next term, 5.3e-10·ϑ¹⁰, is far below rounding there).
constexpr double kInverseJacobianSeriesBelow = 1e-2;  // ϑ²
template <class T>
T inverse_jacobian_coefficient(const T& angle_squared) {
  const T& x = angle_squared;
  if (value_of(x) < kInverseJacobianSeriesBelow)
    return T(1.0 / 12.0) +
           x * (T(1.0 / 720.0) +
                x * (T(1.0 / 30240.0) + x * (T(1.0 / 1209600.0) + x * T(1.0 / 47900160.0))));
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T angle = sqrt(x);
  return T(1) / x - (T(1) + cos(angle)) / (T(2) * angle * sin(angle));
}

// β'(ϑ)/ϑ, so that ∂β/∂φ = β'(ϑ)/ϑ·φᵀ: −2/ϑ⁴ + 1/(4ϑ²·sin²(ϑ/2)) + cot(ϑ/2)/(2ϑ³), below
// ϑ = 0.1 its series 1/360 + ϑ²/7560 + ϑ⁴/201600 + ϑ⁶/5987520 + ϑ⁸/189243758.
inline double inverse_jacobian_slope(double angle_squared) {
  const double x = angle_squared;
  if (x < kInverseJacobianSeriesBelow)
    return 1.0 / 360.0 +
           x * (1.0 / 7560.0 + x * (1.0 / 201600.0 + x * (1.0 / 5987520.0 + x / 189243758.0)));
  const double angle = std::sqrt(x), half_sine = std::sin(0.5 * angle);
  return -2 / (x * x) + 1 / (4 * x * half_sine * half_sine) +
         std::cos(0.5 * angle) / (half_sine * 2 * x * angle);
}

// The derivative of the rotation vector under a turn in front: where A = exp([φ×]) becomes
// (I + [ω×])·A, φ becomes φ + J⁻¹(φ)·ω with J⁻¹(φ) = I − ½·[φ×] + β(|φ|)·[φ×]² (the inverse of
// the left Jacobian of the rotations, valid to |φ| < π).
template <class T>
Mat3T<T> inverse_left_jacobian(const Vec3T<T>& phi) {
  const Mat3T<T> cross = skew_of(phi);
  return Mat3T<T>::Identity() - T(0.5) * cross +
         inverse_jacobian_coefficient(phi.squaredNorm()) * (cross * cross);
}

// J⁻¹(φ)ᵀ·v = v + ½·φ × v + β·φ × (φ × v): the moment whose work on ω is v's on δφ.
template <class T>
Vec3T<T> inverse_left_jacobian_transposed_times(const Vec3T<T>& phi, const Vec3T<T>& v) {
  const Vec3T<T> once = phi.cross(v);
  return v + T(0.5) * once + inverse_jacobian_coefficient(phi.squaredNorm()) * phi.cross(once);
}

// exp([φ×]) by Rodrigues' formula.
inline Mat3 rotation_matrix(const Vec3& phi) {
  const double angle = phi.norm();
  if (angle == 0) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

// The rotation vector of a rotation matrix in double.
inline Vec3 rotation_vector_of(const Mat3& rotation) { return rotation_vector<double>(rotation); }

}  // namespace stiffmsa::detail
