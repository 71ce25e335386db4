#pragma once
// CAD-based links (paper ref. [13]): a given 12×12 free-free stiffness, or the 6×6 compliance
// of one end with the other clamped, turned into the global 12×12 stiffness of eq. (1).
#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

Mat12 matrix_link_global_stiffness(const MatrixLink& link, const Vec3& from, const Vec3& to);
Mat12 compliance_link_global_stiffness(const ComplianceLink& link, const Vec3& from,
                                       const Vec3& to);

}  // namespace stiffmsa::detail
