#include "analysis/free_motion.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <sstream>

#include "stiffmsa/config.hpp"
#if STIFFMSA_HAVE_SUITESPARSE
#include <Eigen/SPQRSupport>
#endif

#include "analysis/cartesian.hpp"
#include "elements/free_directions.hpp"
#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

namespace {

// Above this many unknowns the null spaces are not computed densely.
constexpr Index kDenseLimit = 2400;
constexpr double kNegligible = kNegligibleNullEntry;

double weighted_norm(const Vec6& t, double length) { return t.head<3>().norm() + length * t.tail<3>().norm(); }

std::string list(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i ? ", " : "") + names[i];
  return text;
}

MatX deflection_rows(const MatX& v, int ends) {
  MatX rows(6 * static_cast<Index>(ends), v.cols());
  for (int e = 0; e < ends; ++e) rows.middleRows<6>(6 * e) = v.middleRows<6>(deflection_column(e));
  return rows;
}

std::string describe_motion(const Model& model, const Topology& topology, const VecX& motion, double length) {
  auto deflection = [&](int end) -> Vec6 { return motion.segment<6>(deflection_column(end)); };
  double largest = 0;
  for (int end = 0; end < topology.end_count(); ++end) largest = std::max(largest, weighted_norm(deflection(end), length));
  const double significant = 1e-6 * largest;

  std::vector<std::string> joints, links, effectors;
  for (const auto& group : topology.groups) {
    if (group.kind != ConnectionGroup::Kind::joint) continue;
    const Joint& joint = model.joints[static_cast<std::size_t>(group.source)];
    const auto directions = free_directions(joint.connection.kinematics);
    if (directions.free().rows() == 0 || joint.connection.stiffness || joint.connection.actuated) continue;
    const MatX projector = directions.free().transpose() * directions.gram().inverse() * directions.free();
    for (std::size_t k = 1; k < group.ends.size(); ++k) {
      const Vec6 relative = projector * (deflection(group.ends[k]) - deflection(group.ends.front()));
      if (weighted_norm(relative, length) > significant) {
        joints.push_back("'" + joint.name + "' (" + to_string(joint.connection.kinematics.type) + " at " + joint.at + ")");
        break;
      }
    }
  }
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const int from = 2 * static_cast<int>(l);
    if (weighted_norm(deflection(from), length) > significant || weighted_norm(deflection(from + 1), length) > significant)
      links.push_back("'" + model.links[l].name + "'");
  }
  for (std::size_t e = 0; e < model.end_effectors.size(); ++e)
    if (weighted_norm(deflection(topology.effector_ends[e]), length) > significant)
      effectors.push_back("'" + model.end_effectors[e].name + "'");

  std::ostringstream text;
  if (!joints.empty())
    text << (joints.size() == 1 ? "joint " : "joints ") << list(joints) << " can move freely";
  else
    text << (links.size() == 1 ? "link " : "links ") << list(links) << " can move without resistance";
  if (!joints.empty() && !links.empty()) text << ", moving " << (links.size() == 1 ? "link " : "links ") << list(links);
  if (effectors.empty())
    text << "; it moves no end effector " << kAcceptIdleMotionHint;
  else
    text << "; it moves end effector" << (effectors.size() == 1 ? " " : "s ") << list(effectors);
  return text.str();
}

std::string describe_redundancy(const Model& model, const MatX& redundancies) {
  std::vector<std::string> links;
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const int from = 2 * static_cast<int>(l);
    const double change = redundancies.middleRows<6>(wrench_column(from)).norm() + redundancies.middleRows<6>(wrench_column(from + 1)).norm();
    if (change > kNegligible * redundancies.norm()) links.push_back("'" + model.links[l].name + "'");
  }
  std::ostringstream text;
  text << "the structure is over-constrained (" << redundancies.cols()
       << (redundancies.cols() == 1 ? " redundant constraint" : " redundant constraints")
       << "): a rigid model does not determine the internal wrenches in the loop through "
       << (links.size() == 1 ? "link " : "links ") << list(links) << "; they are reported as null";
  return text.str();
}

}  // namespace

#if STIFFMSA_HAVE_SUITESPARSE
namespace {
// The same from SuiteSparseQR's rank-revealing sparse QR, for systems too large for a dense
// decomposition: with Âᵀ = Q·R, the columns of Q past the rank span the null space of Â (and
// likewise from Â = Q·R for the left null space).
MatX trailing_q_columns(const SparseMatrix& m, Index& rank) {
  Eigen::SPQR<SparseMatrix> qr;
  qr.setPivotThreshold(1e-10);
  qr.compute(m);
  if (qr.info() != Eigen::Success) throw Error("the sparse QR of a singular system failed");
  rank = qr.rank();
  const Index k = m.rows() - rank;
  MatX selector = MatX::Zero(m.rows(), k);
  for (Index i = 0; i < k; ++i) selector(rank + i, i) = 1.0;
  return qr.matrixQ() * selector;
}

std::optional<NullSpaces> sparse_null_spaces(const SparseMatrix& matrix) {
  const Equilibration scaling = equilibrate(matrix);
  SparseMatrix scaled = matrix;
  for (Index j = 0; j < scaled.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(scaled, j); e; ++e) e.valueRef() *= scaling.row(e.row()) * scaling.column(j);
  NullSpaces spaces;
  spaces.column_scale = scaling.column;
  Index rank = 0;
  const SparseMatrix transposed = scaled.transpose();
  spaces.right_equilibrated = trailing_q_columns(transposed, rank);
  if (spaces.right_equilibrated.cols() == 0) {
    spaces.left.resize(matrix.rows(), 0);
    return spaces;
  }
  spaces.left = scaling.row.asDiagonal() * trailing_q_columns(scaled, rank);
  return spaces;
}
}  // namespace
#endif

std::optional<NullSpaces> null_spaces(const SparseMatrix& matrix) {
#if STIFFMSA_HAVE_SUITESPARSE
  if (matrix.rows() > kDenseLimit) return sparse_null_spaces(matrix);
#else
  if (matrix.rows() > kDenseLimit) return std::nullopt;
#endif
  const Equilibration scaling = equilibrate(matrix);
  const MatX scaled = scaling.row.asDiagonal() * MatX(matrix) * scaling.column.asDiagonal();
  NullSpaces spaces;
  spaces.column_scale = scaling.column;
  Eigen::FullPivLU<MatX> lu(scaled);
  lu.setThreshold(1e-10);
  if (lu.rank() == matrix.rows()) {
    spaces.right_equilibrated.resize(matrix.rows(), 0);
    spaces.left.resize(matrix.rows(), 0);
    return spaces;
  }
  spaces.right_equilibrated = Eigen::JacobiSVD<MatX>(lu.kernel(), Eigen::ComputeThinU).matrixU();
  Eigen::FullPivLU<MatX> lu_transposed(scaled.transpose());
  lu_transposed.setThreshold(1e-10);
  spaces.left = scaling.row.asDiagonal() * lu_transposed.kernel();
  return spaces;
}

SingularStructure analyse_singular_structure(const Model& model, const Topology& topology, const SparseMatrix& matrix) {
  SingularStructure s;
  const auto spaces = null_spaces(matrix);
  if (!spaces) {
    s.descriptions.push_back("the system (" + std::to_string(matrix.rows()) +
                             " unknowns) is singular: part of the structure can move freely or is over-constrained");
    return s;
  }
  s.analysed = true;
  if (spaces->right_equilibrated.cols() == 0) {
    s.descriptions.push_back("the system is nearly singular (ill-conditioned) but has no exact free motion");
    return s;
  }
  const MatX& null_basis = spaces->right_equilibrated;
  s.left_null = spaces->left;

  // Split the null space: directions with a deflection part move something, the rest (the
  // null space of the deflection rows) change wrenches only.
  const MatX moving = deflection_rows(null_basis, topology.end_count());
  const Eigen::JacobiSVD<MatX> split(moving, Eigen::ComputeFullV);
  Index motion_count = 0;
  for (Index i = 0; i < split.singularValues().size(); ++i) motion_count += split.singularValues()(i) > kNegligible;
  const MatX v = split.matrixV();
  s.motions = spaces->column_scale.asDiagonal() * (null_basis * v.leftCols(motion_count));
  s.redundancies = spaces->column_scale.asDiagonal() * (null_basis * v.rightCols(v.cols() - motion_count));

  const double length = characteristic_length(model);
  if (motion_count > 0) {
    std::ostringstream head;
    head << motion_count << (motion_count == 1 ? " free motion" : " free motions") << " (degrees of freedom)";
    s.descriptions.push_back(head.str());
    for (Index c = 0; c < motion_count; ++c)
      s.descriptions.push_back("free motion " + std::to_string(c + 1) + ": " +
                               describe_motion(model, topology, s.motions.col(c), length));
  }
  if (s.redundancies.cols() > 0) s.descriptions.push_back(describe_redundancy(model, s.redundancies));
  return s;
}

}  // namespace stiffmsa::detail
