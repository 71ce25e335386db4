#include "analysis/cartesian.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <limits>

#include "stiffmsa/analysis.hpp"

namespace stiffmsa {

namespace detail {

double characteristic_length(const Model& model) {
  if (model.points.empty()) return 1.0;
  Vec3 low = model.points.front().position, high = low;
  for (const auto& p : model.points) {
    low = low.cwiseMin(p.position);
    high = high.cwiseMax(p.position);
  }
  return std::max((high - low).norm(), 1e-3);
}

namespace {
Vec6 weighted_eigenvalues(const Mat6& compliance, double length) {
  Vec6 weights;
  weights << 1, 1, 1, length, length, length;
  const Mat6 weighted = weights.asDiagonal() * compliance * weights.asDiagonal();
  return Eigen::SelfAdjointEigenSolver<Mat6>(0.5 * (weighted + weighted.transpose()), Eigen::EigenvaluesOnly).eigenvalues();
}
}  // namespace

CartesianStiffness cartesian_stiffness(const Mat6& compliance, double length) {
  const Vec6 values = weighted_eigenvalues(compliance, length);
  CartesianStiffness result;
  result.spread = values(0) > 0 ? values(5) / values(0) : std::numeric_limits<double>::infinity();
  if (values(5) > 0 && values(0) > 1e-14 * values(5)) result.stiffness = Mat6(compliance.fullPivLu().inverse());
  return result;
}

}  // namespace detail

namespace {
Vec3 block_stiffness(const Mat3& compliance_block) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(0.5 * (compliance_block + compliance_block.transpose()),
                                                  Eigen::EigenvaluesOnly);
  const Vec3& c = eigen.eigenvalues();
  Vec3 k;
  for (int i = 0; i < 3; ++i)
    k(i) = (c(i) > 1e-12 * std::max(c(2), 0.0) && c(i) > 0) ? 1.0 / c(i) : std::numeric_limits<double>::infinity();
  std::sort(k.data(), k.data() + 3);
  return k;
}
}  // namespace

PrincipalStiffness principal_stiffness(const Mat6& compliance) {
  return {block_stiffness(compliance.topLeftCorner<3, 3>()), block_stiffness(compliance.bottomRightCorner<3, 3>())};
}

const char* to_string(SolverKind s) {
  switch (s) {
    case SolverKind::automatic: return "auto";
    case SolverKind::sparse_lu: return "sparse_lu";
    case SolverKind::umfpack: return "umfpack";
    case SolverKind::klu: return "klu";
  }
  return "?";
}

std::optional<SolverKind> solver_kind_from_string(const std::string& s) {
  for (SolverKind k : {SolverKind::automatic, SolverKind::sparse_lu, SolverKind::umfpack, SolverKind::klu})
    if (s == to_string(k)) return k;
  return std::nullopt;
}

}  // namespace stiffmsa
