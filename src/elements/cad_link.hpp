#pragma once
// CAD-based links (paper ref. [13]): a given 12×12 free-free stiffness, or the 6×6 compliance
// of one end with the other clamped, in global axes.
#include <optional>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

Mat12 matrix_link_global_stiffness(const MatrixLink& link, const Vec3& from, const Vec3& to);
Mat6 compliance_link_global_compliance(const ComplianceLink& link, const Vec3& from,
                                       const Vec3& to);

// The free-free stiffness of a link from its clamped-end compliance C and d = p_to − p_from:
// K12 = [[DᵀKD, −DᵀK], [−KD, K]], K = C⁻¹.
Mat12 free_free_stiffness(const Mat6& compliance, const Vec3& d);

// C = K22⁻¹ of a free-free stiffness, or nullopt where K22 is not positive definite.
std::optional<Mat6> clamped_compliance(const Mat12& free_free);

}  // namespace stiffmsa::detail
