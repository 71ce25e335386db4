#include "analysis/free_motion.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <sstream>

#include "analysis/cartesian.hpp"
#include "elements/free_directions.hpp"
#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

namespace {

// Above this many unknowns the null space is not computed densely.
constexpr Index kDenseLimit = 2400;

double weighted_norm(const Vec6& t, double length) { return t.head<3>().norm() + length * t.tail<3>().norm(); }

std::string list(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i ? ", " : "") + names[i];
  return text;
}

std::string describe(const Model& model, const Topology& topology, const VecX& motion, double length) {
  auto deflection = [&](int end) -> Vec6 { return motion.segment<6>(deflection_column(end)); };
  double largest = 0;
  for (int end = 0; end < topology.end_count(); ++end) largest = std::max(largest, weighted_norm(deflection(end), length));
  const double significant = 1e-6 * largest;

  std::vector<std::string> joints, links, effectors;
  for (const auto& group : topology.groups) {
    if (group.kind != ConnectionGroup::Kind::joint) continue;
    const Joint& joint = model.joints[static_cast<std::size_t>(group.source)];
    const auto directions = free_directions(joint.connection.kinematics);
    if (directions.free.rows() == 0 || joint.connection.stiffness || joint.connection.actuated) continue;
    const MatX projector = directions.free.transpose() * directions.gram().ldlt().solve(directions.free);
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
    text << "; it moves no end effector (an idle motion)";
  else
    text << "; it moves end effector" << (effectors.size() == 1 ? " " : "s ") << list(effectors);
  return text.str();
}

}  // namespace

FreeMotions describe_free_motions(const Model& model, const Topology& topology, const SparseMatrix& matrix) {
  FreeMotions result;
  if (matrix.rows() > kDenseLimit) {
    result.descriptions.push_back("the system (" + std::to_string(matrix.rows()) +
                                  " unknowns) is singular: some part of the structure can move freely");
    return result;
  }
  const Equilibration scaling = equilibrate(matrix);
  const MatX scaled = scaling.row.asDiagonal() * MatX(matrix) * scaling.column.asDiagonal();
  Eigen::FullPivLU<MatX> lu(scaled);
  lu.setThreshold(1e-10);
  const MatX kernel = scaling.column.asDiagonal() * lu.kernel();
  if (lu.rank() == matrix.rows()) {
    result.count = 0;
    result.descriptions.push_back("the system is nearly singular (ill-conditioned) but has no exact free motion");
    return result;
  }
  result.count = static_cast<int>(kernel.cols());
  const double length = characteristic_length(model);
  std::ostringstream head;
  head << result.count << (result.count == 1 ? " free motion" : " free motions") << " (degrees of freedom)";
  result.descriptions.push_back(head.str());
  for (Index c = 0; c < kernel.cols(); ++c)
    result.descriptions.push_back("free motion " + std::to_string(c + 1) + ": " +
                                  describe(model, topology, kernel.col(c), length));
  return result;
}

}  // namespace stiffmsa::detail
