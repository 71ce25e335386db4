#pragma once
// Dense linear-algebra vocabulary shared by the whole library.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace stiffmsa {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

// [v×]: the matrix with skew(v)·w = v × w.
inline Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// Paper eq. (2): D = [[I, [d×]ᵀ], [0, I]] carries a small motion of a rigid body from the point
// p_i to the point p_j = p_i + d (Δp_j = Δp_i + Δφ × d).
inline Mat6 rigid_transport(const Vec3& d) {
  Mat6 D = Mat6::Identity();
  D.block<3, 3>(0, 3) = skew(d).transpose();
  return D;
}

// The size of a model's mixed system (the assembly's, reported by check() and in results).
struct SystemSize {
  long unknowns = 0;
  long equations = 0;
  long nonzeros = 0;
};

}  // namespace stiffmsa
