#include "elements/cad_link.hpp"

#include <Eigen/Cholesky>

#include "elements/beam_element.hpp"

namespace stiffmsa::detail {

Mat12 matrix_link_global_stiffness(const MatrixLink& link, const Vec3& from, const Vec3& to) {
  if (link.frame == LinkFrame::global) return link.K;
  const Mat12 T = link_rotation12(link_axes(from, to, link.zref));
  return T.transpose() * link.K * T;
}

Mat12 compliance_link_global_stiffness(const ComplianceLink& link, const Vec3& from,
                                       const Vec3& to) {
  Mat6 C = link.C;
  if (link.frame == LinkFrame::local) {
    const Mat3 R = link_axes(from, to, link.zref);
    Mat6 R6 = Mat6::Zero();
    R6.block<3, 3>(0, 0) = R;
    R6.block<3, 3>(3, 3) = R;
    C = R6.transpose() * C * R6;
  }
  const Eigen::LDLT<Mat6> ldlt(C);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive())
    throw InputError({}, "C", "the compliance matrix must be symmetric positive definite");
  const Mat6 K = ldlt.solve(Mat6::Identity());
  // End `to` deflects by Δt_to − D·Δt_from relative to the clamped end carried rigidly.
  const Mat6 D = rigid_transport(to - from);
  Mat12 K12;
  K12.block<6, 6>(0, 0) = D.transpose() * K * D;
  K12.block<6, 6>(0, 6) = -D.transpose() * K;
  K12.block<6, 6>(6, 0) = -K * D;
  K12.block<6, 6>(6, 6) = K;
  return K12;
}

}  // namespace stiffmsa::detail
