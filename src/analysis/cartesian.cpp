#include "analysis/cartesian.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "stiffmsa/analysis.hpp"
#include "tolerances.hpp"

namespace stiffmsa {

namespace detail {

double characteristic_length(const Model& model) {
  if (model.points.empty()) return 1.0;
  Vec3 low = model.points.front().position, high = low;
  for (const auto& p : model.points) {
    low = low.cwiseMin(p.position);
    high = high.cwiseMax(p.position);
  }
  return std::max((high - low).norm(), kLeastModelSize);
}

namespace {

// C⁻¹ by an LU with partial pivoting, solved a column at a time: Eigen's inverse() of a 6×6
// LU goes through its blocked matrix solve, three times the instructions of six vector solves.
Mat6 inverse(const Mat6& c) {
  const Eigen::PartialPivLU<Mat6> lu(c);
  Mat6 k;
  for (int column = 0; column < 6; ++column) k.col(column) = lu.solve(Vec6::Unit(column));
  return k;
}
}  // namespace

CartesianStiffness cartesian_stiffness(const Mat6& compliance, double length,
                                       double spread_threshold) {
  Vec6 weights;
  weights << 1, 1, 1, length, length, length;
  const Mat6 weighted = weights.asDiagonal() * compliance * weights.asDiagonal();
  const Mat6 symmetric = 0.5 * (weighted + weighted.transpose());
  CartesianStiffness result;
  // The common case, a well-conditioned compliance, without an eigen-decomposition: for the
  // symmetric positive definite Ĉ = L·Lᵀ, λ_max ≤ tr(Ĉ) and 1/λ_min ≤ tr(Ĉ⁻¹) = ‖L⁻¹‖²_F.
  // (A NaN passes Eigen's Cholesky; it fails the comparison below.)
  const Eigen::LLT<Mat6> cholesky(symmetric);
  if (cholesky.info() == Eigen::Success) {
    double inverse_trace = 0;
    for (int c = 0; c < 6; ++c)
      inverse_trace += cholesky.matrixL().solve(Vec6::Unit(c)).squaredNorm();
    const double bound = symmetric.trace() * inverse_trace;
    if (bound > 0 && bound <= std::min(spread_threshold, kRigidSpread)) {
      result.spread = bound;
      // C itself, not its symmetric part: a stiffness matrix given to ~10 digits leaves C
      // unsymmetric at that level, and K is its inverse on both paths.
      result.stiffness = inverse(compliance);
      return result;
    }
  }
  const Vec6 values =
      Eigen::SelfAdjointEigenSolver<Mat6>(symmetric, Eigen::EigenvaluesOnly).eigenvalues();
  result.spread = values(0) > 0 ? values(5) / values(0) : std::numeric_limits<double>::infinity();
  if (values(5) > 0 && values(0) * kRigidSpread > values(5))
    result.stiffness = Mat6(compliance.fullPivLu().inverse());
  return result;
}

std::optional<ReducedStiffness> reduced_stiffness(const Mat6& compliance, double length) {
  Vec6 weights;
  weights << 1, 1, 1, length, length, length;
  const Mat6 weighted = weights.asDiagonal() * compliance * weights.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Mat6> eigen(0.5 * (weighted + weighted.transpose()));
  const Vec6& values = eigen.eigenvalues();
  const double largest = values(5);
  if (!(largest > 0)) return std::nullopt;
  Eigen::Index held = 0;
  while (values(held) * kRigidSpread <= largest) ++held;  // stops at 5 at the latest
  if (held == 0) return std::nullopt;
  const Eigen::Index moving = 6 - held;
  // A coordinate axis whose own compliance is at rounding level is held: it takes no part in
  // the directions. Where those axes are all that is held (a planar robot: z, rx, ry), the
  // directions are the other axes exactly, and K_r is the inverse of C's block on them.
  std::vector<int> moving_axes, held_axes;
  for (int axis = 0; axis < 6; ++axis)
    (weighted(axis, axis) * kRigidSpread > largest ? moving_axes : held_axes).push_back(axis);
  ReducedStiffness reduced;
  reduced.directions = MatX::Zero(moving, 6);
  if (static_cast<Eigen::Index>(moving_axes.size()) == moving) {
    for (Eigen::Index k = 0; k < moving; ++k)
      reduced.directions(k, moving_axes[static_cast<std::size_t>(k)]) = 1;
  } else {
    // The range of C is W⁻¹ times that of Ĉ = W·C·W; an orthonormal basis of it, each
    // direction signed so that its largest entry is positive.
    MatX span = weights.cwiseInverse().asDiagonal() * eigen.eigenvectors().rightCols(moving);
    for (int axis : held_axes) span.row(axis).setZero();
    const Eigen::HouseholderQR<MatX> qr(span);
    reduced.directions = (qr.householderQ() * MatX::Identity(6, moving)).transpose();
    for (Eigen::Index k = 0; k < moving; ++k) {
      Eigen::Index at = 0;
      reduced.directions.row(k).cwiseAbs().maxCoeff(&at);
      if (reduced.directions(k, at) < 0) reduced.directions.row(k) *= -1;
    }
  }
  reduced.matrix =
      MatX(reduced.directions * compliance * reduced.directions.transpose()).fullPivLu().inverse();
  return reduced;
}

}  // namespace detail

namespace {

double stiffness_of(double compliance, double largest) {
  return (compliance > detail::kRigidCompliance * std::max(largest, 0.0) && compliance > 0)
             ? 1.0 / compliance
             : std::numeric_limits<double>::infinity();
}

// Eigenvalues of the block's inverse, ascending, with their eigenvectors: the compliance's
// eigenvalues descending, inverted.
void block_stiffness(const Mat3& compliance_block, Vec3& values, Mat3& directions) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(
      0.5 * (compliance_block + compliance_block.transpose()));
  const Vec3& c = eigen.eigenvalues();
  for (int i = 0; i < 3; ++i) {
    values(i) = stiffness_of(c(2 - i), c(2));
    Vec3 direction = eigen.eigenvectors().col(2 - i);
    Eigen::Index largest = 0;
    direction.cwiseAbs().maxCoeff(&largest);
    directions.col(i) = direction(largest) < 0 ? Vec3(-direction) : direction;
  }
}
}  // namespace

PrincipalStiffness principal_stiffness(const Mat6& compliance) {
  PrincipalStiffness principal;
  block_stiffness(compliance.topLeftCorner<3, 3>(), principal.translational,
                  principal.translational_directions);
  block_stiffness(compliance.bottomRightCorner<3, 3>(), principal.rotational,
                  principal.rotational_directions);
  return principal;
}

PrincipalAxes principal_axes(const Mat3& compliance_block) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(
      0.5 * (compliance_block + compliance_block.transpose()));
  const Vec3& c = eigen.eigenvalues();
  return {c, eigen.eigenvectors(),
          Vec3(stiffness_of(c(0), c(2)), stiffness_of(c(1), c(2)), stiffness_of(c(2), c(2)))};
}

DirectionalStiffness directional_stiffness(const Mat6& compliance, const Vec3& direction) {
  const double length = direction.norm();
  if (!std::isfinite(length) || length == 0)
    throw UsageError("the direction of a directional stiffness must be a finite, non-zero vector");
  const Vec3 u = direction / length;
  const Mat3 translational = compliance.topLeftCorner<3, 3>(),
             rotational = compliance.bottomRightCorner<3, 3>();
  return {u, stiffness_of(u.dot(translational * u), translational.diagonal().maxCoeff()),
          stiffness_of(u.dot(rotational * u), rotational.diagonal().maxCoeff())};
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
  for (SolverKind k :
       {SolverKind::automatic, SolverKind::sparse_lu, SolverKind::umfpack, SolverKind::klu})
    if (s == to_string(k)) return k;
  return std::nullopt;
}

}  // namespace stiffmsa
