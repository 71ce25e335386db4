#include "elements/cad_link.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "elements/beam_element.hpp"
#include "tolerances.hpp"

namespace stiffmsa::detail {

Mat12 matrix_link_global_stiffness(const MatrixLink& link, const Vec3& from, const Vec3& to) {
  if (link.frame == LinkFrame::global) return link.K;
  const Mat12 T = link_rotation12(link_axes(from, to, link.zref));
  return T.transpose() * link.K * T;
}

Mat6 compliance_link_global_compliance(const ComplianceLink& link, const Vec3& from,
                                       const Vec3& to) {
  if (link.frame == LinkFrame::global) return link.C;
  const Mat6 R = rotation6(link_axes(from, to, link.zref));
  return R.transpose() * link.C * R;
}

Mat12 free_free_stiffness(const Mat6& compliance, const Vec3& d) {
  const Mat6 K = compliance.ldlt().solve(Mat6::Identity());
  const Mat6 D = rigid_transport(d);
  Mat12 K12;
  K12.block<6, 6>(0, 0) = D.transpose() * K * D;
  K12.block<6, 6>(0, 6) = -D.transpose() * K;
  K12.block<6, 6>(6, 0) = -K * D;
  K12.block<6, 6>(6, 6) = K;
  return K12;
}

std::optional<Mat6> clamped_compliance(const Mat12& free_free) {
  const Mat6 K22 =
      0.5 * (free_free.bottomRightCorner<6, 6>() + free_free.bottomRightCorner<6, 6>().transpose());
  const Eigen::SelfAdjointEigenSolver<Mat6> eigen(K22, Eigen::EigenvaluesOnly);
  const Vec6& k = eigen.eigenvalues();
  if (!(k(5) > 0) || !(k(0) > kClampedSpread * k(5))) return std::nullopt;
  return Mat6(K22.llt().solve(Mat6::Identity()));
}

}  // namespace stiffmsa::detail
