#include "elements/geometric_load_terms.hpp"

#include <Eigen/Cholesky>

namespace stiffmsa::detail {

Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

Mat12 chord_load_stiffness(const Vec3& force_to) {
  Mat12 k = Mat12::Zero();
  const Mat3 f = cross_matrix(force_to);
  k.block<3, 3>(3, 6) = f;
  k.block<3, 3>(3, 0) = -f;
  return k;
}

MatX joint_load_stiffness(const FreeDirections& directions, const std::vector<Vec6>& reactions) {
  const Eigen::Index m = static_cast<Eigen::Index>(reactions.size());
  MatX k = MatX::Zero(6 * m, 6 * m);
  if (directions.p == 0) return k;
  const MatX free = directions.free();
  const Mat6 projection = free.transpose() * directions.gram().ldlt().solve(free);
  for (Eigen::Index e = 0; e < m; ++e) {
    const Vec6& r = reactions[static_cast<std::size_t>(e)];
    Eigen::Matrix<double, 6, 3> turned;
    turned.topRows<3>() = cross_matrix(r.head<3>());
    turned.bottomRows<3>() = cross_matrix(r.tail<3>());
    k.block<6, 3>(6 * e, 3) += projection * turned;
    const Mat3 lever = cross_matrix(r.head<3>());
    k.block<3, 3>(6 * e + 3, 6 * e) -= lever;
    k.block<3, 3>(6 * e + 3, 0) += lever;
  }
  return k;
}

}  // namespace stiffmsa::detail
