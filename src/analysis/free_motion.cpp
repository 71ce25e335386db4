#include "analysis/free_motion.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <numeric>
#include <sstream>

#include "stiffmsa/config.hpp"
#if STIFFMSA_HAVE_SUITESPARSE
#include <Eigen/SPQRSupport>
#endif

#include "analysis/cartesian.hpp"
#include "elements/free_directions.hpp"
#include "model/suggest.hpp"
#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

namespace {

// Above this many unknowns the null spaces are not computed densely.
constexpr Index kDenseLimit = 2400;
constexpr double kNegligible = kNegligibleNullEntry;

double weighted_norm(const Vec6& t, double length) {
  return t.head<3>().norm() + length * t.tail<3>().norm();
}

std::string counted(std::size_t count, const char* singular, const char* plural) {
  return count == 1 ? singular : plural;
}

MatX deflection_rows(const MatX& v, int ends) {
  MatX rows(6 * static_cast<Index>(ends), v.cols());
  for (int e = 0; e < ends; ++e) rows.middleRows<6>(6 * e) = v.middleRows<6>(deflection_column(e));
  return rows;
}

// The link ends that no support reaches through links, joints, supports and welds: per end, the
// number of its unsupported part, or −1 where a support holds its part.
std::vector<int> unsupported_parts(const Topology& topology) {
  std::vector<int> root(static_cast<std::size_t>(topology.end_count()));
  std::iota(root.begin(), root.end(), 0);
  // Path halving keeps the trees shallow: a chain of 100 000 links stays linear.
  auto find = [&](int end) {
    while (root[static_cast<std::size_t>(end)] != end) {
      int& up = root[static_cast<std::size_t>(end)];
      up = root[static_cast<std::size_t>(up)];
      end = up;
    }
    return end;
  };
  auto join = [&](int a, int b) { root[static_cast<std::size_t>(find(a))] = find(b); };
  for (int link = 0; link < topology.link_count; ++link) join(2 * link, 2 * link + 1);
  for (const auto& group : topology.groups)
    for (int end : group.ends) join(end, group.ends.front());
  std::vector<bool> supported(root.size(), false);
  for (const auto& group : topology.groups)
    if (group.kind == ConnectionGroup::Kind::support)
      supported[static_cast<std::size_t>(find(group.ends.front()))] = true;
  std::vector<int> part(root.size(), -1), number(root.size(), -1);
  int parts = 0;
  for (int end = 0; end < topology.end_count(); ++end) {
    const int r = find(end);
    if (supported[static_cast<std::size_t>(r)]) continue;
    if (number[static_cast<std::size_t>(r)] < 0) number[static_cast<std::size_t>(r)] = parts++;
    part[static_cast<std::size_t>(end)] = number[static_cast<std::size_t>(r)];
  }
  return part;
}

// What holds no part of the model: said once per part, with the likely cause where there is one
// (a link end alone at a point that stands where another point is: two names, two points).
std::vector<std::string> describe_unsupported_parts(const Model& model, const Topology& topology,
                                                    const std::vector<int>& part, double length) {
  const int parts = part.empty() ? 0 : 1 + *std::max_element(part.begin(), part.end());
  if (parts == 0) return {};
  if (model.supports.empty())
    return {
        "the model has no support: nothing holds it, so it can move as a whole; add one under "
        "`supports:`"};
  std::vector<std::string> lines;
  for (int p = 0; p < parts; ++p) {
    std::vector<std::string> causes, links;
    for (int link = 0; link < topology.link_count; ++link)
      if (part[static_cast<std::size_t>(2 * link)] == p)
        links.push_back("'" + model.links[static_cast<std::size_t>(link)].name + "'");
    for (const auto& group : topology.groups) {
      if (group.kind != ConnectionGroup::Kind::free_end ||
          part[static_cast<std::size_t>(group.ends.front())] != p)
        continue;
      const int end = group.ends.front();
      const Point& own =
          model
              .points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(end)])];
      for (std::size_t other = 0; other < topology.end_points.size(); ++other) {
        const Point& there = model.points[static_cast<std::size_t>(topology.end_points[other])];
        if (part[other] == p || there.name == own.name ||
            (there.position - own.position).norm() > kSamePlace * length)
          continue;
        causes.push_back("link '" + model.links[static_cast<std::size_t>(end / 2)].name +
                         "' is connected to nothing at its " + (end % 2 == 0 ? "start" : "end") +
                         ": its point '" + own.name + "' stands where point '" + there.name +
                         "' is, but points are told apart by name, not by coordinates");
        break;
      }
    }
    if (causes.empty())
      lines.push_back(
          links.size() == 1
              ? "link " + links.front() +
                    " is held by no support: no joint, support or shared point joins it "
                    "to a supported part, so it can move as a whole"
              : "links " + name_list(links) +
                    " are held by no support: no joint, support or shared point joins "
                    "them to a supported part, so they can move as a whole");
    else
      lines.insert(lines.end(), causes.begin(), causes.end());
  }
  return lines;
}

// A passive joint or support (no stiffness, not actuated, some free direction): what lets a
// free motion happen.
struct PassiveConnection {
  bool support = false;
  std::string label;                       // "'motor2' (revolute at B2)"
  std::vector<std::pair<int, int>> moves;  // (end, reference end; −1: the ground)
  Mat6 projector;                          // onto the free directions
};

std::vector<PassiveConnection> passive_connections(const Model& model, const Topology& topology,
                                                   const std::vector<int>& part) {
  std::vector<PassiveConnection> passive;
  for (const auto kind : {ConnectionGroup::Kind::support, ConnectionGroup::Kind::joint}) {
    for (const auto& group : topology.groups) {
      if (group.kind != kind || part[static_cast<std::size_t>(group.ends.front())] >= 0) continue;
      const bool support = kind == ConnectionGroup::Kind::support;
      const std::size_t source = static_cast<std::size_t>(group.source);
      const std::string& name = support ? model.supports[source].name : model.joints[source].name;
      const std::string& at = support ? model.supports[source].at : model.joints[source].at;
      const Connection& connection =
          support ? model.supports[source].connection : model.joints[source].connection;
      const auto directions = free_directions(connection.kinematics);
      if (directions.free().rows() == 0 || connection.stiffness || connection.is_actuated) continue;
      PassiveConnection c;
      c.support = support;
      c.label = "'" + name + "' (" + to_string(connection.kinematics.type) + " at " + at + ")";
      c.projector = directions.free().transpose() * directions.gram().inverse() * directions.free();
      if (support)
        c.moves.emplace_back(group.ends.front(), -1);
      else
        for (std::size_t k = 1; k < group.ends.size(); ++k)
          c.moves.emplace_back(group.ends[k], group.ends.front());
      passive.push_back(std::move(c));
    }
  }
  return passive;
}

// The motion a passive connection lets happen in each column of `motions`, rotations weighed
// by `length`: 6 rows per moving end.
MatX passive_motion_rows(const std::vector<PassiveConnection>& passive, const MatX& motions,
                         double length) {
  Index rows = 0;
  for (const auto& c : passive) rows += 6 * static_cast<Index>(c.moves.size());
  MatX g(rows, motions.cols());
  Vec6 weights;
  weights << 1, 1, 1, length, length, length;
  Index row = 0;
  for (const auto& c : passive)
    for (const auto& [end, reference] : c.moves) {
      MatX relative = motions.middleRows<6>(deflection_column(end));
      if (reference >= 0) relative -= motions.middleRows<6>(deflection_column(reference));
      g.middleRows<6>(row) = weights.asDiagonal() * (c.projector * relative);
      row += 6;
    }
  return g;
}

// Another basis of the same free motions, row-reduced (Gauss–Jordan) by the motions of the
// passive connections in their order: each motion moves as few of them as the structure
// allows, so that independent mechanisms (two legs, each with a passive joint) get a motion
// each rather than mixtures of both.
MatX separated_motions(const MatX& motions, const MatX& passive_rows) {
  MatX a = passive_rows.transpose();
  MatX combination = MatX::Identity(motions.cols(), motions.cols());
  const double scale = a.size() ? a.cwiseAbs().maxCoeff() : 0.0;
  Index row = 0;
  for (Index column = 0; column < a.cols() && row < a.rows(); ++column) {
    Index pivot = 0;
    const double largest = a.col(column).tail(a.rows() - row).cwiseAbs().maxCoeff(&pivot);
    if (largest <= kTakesPart * scale) continue;
    pivot += row;
    a.row(row).swap(a.row(pivot));
    combination.row(row).swap(combination.row(pivot));
    const double p = a(row, column);
    a.row(row) /= p;
    combination.row(row) /= p;
    for (Index other = 0; other < a.rows(); ++other) {
      if (other == row) continue;
      const double factor = a(other, column);
      a.row(other) -= factor * a.row(row);
      combination.row(other) -= factor * combination.row(row);
    }
    ++row;
  }
  return motions * combination.transpose();
}

// One free motion (`several`: alike motions) in the user's terms: the passive joints and
// supports that let it happen, the links and end effectors it moves. Parts that no support holds
// are described once elsewhere. `names_passive` tells whether it names a joint or support.
std::string describe_motion(const Model& model, const Topology& topology,
                            const std::vector<PassiveConnection>& passive,
                            const std::vector<int>& part, const VecX& motion, double length,
                            bool several, bool& names_passive) {
  auto deflection = [&](int end) -> Vec6 { return motion.segment<6>(deflection_column(end)); };
  double largest = 0;
  for (int end = 0; end < topology.end_count(); ++end)
    if (part[static_cast<std::size_t>(end)] < 0)
      largest = std::max(largest, weighted_norm(deflection(end), length));
  const double significant = kTakesPart * largest;

  std::vector<std::string> supports, joints, links, effectors;
  for (const auto& c : passive)
    for (const auto& [end, reference] : c.moves) {
      const Vec6 relative =
          c.projector * (deflection(end) - (reference >= 0 ? deflection(reference) : Vec6::Zero()));
      if (weighted_norm(relative, length) <= significant) continue;
      (c.support ? supports : joints).push_back(c.label);
      break;
    }
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const int from = 2 * static_cast<int>(l);
    if (part[static_cast<std::size_t>(from)] >= 0) continue;
    if (weighted_norm(deflection(from), length) > significant ||
        weighted_norm(deflection(from + 1), length) > significant)
      links.push_back("'" + model.links[l].name + "'");
  }
  for (std::size_t e = 0; e < model.end_effectors.size(); ++e) {
    const int end = topology.effector_ends[e];
    if (part[static_cast<std::size_t>(end)] < 0 &&
        weighted_norm(deflection(end), length) > significant)
      effectors.push_back("'" + model.end_effectors[e].name + "'");
  }

  const char* subject = several ? "they" : "it";
  const char* moves = several ? " move" : " moves";
  std::vector<std::string> culprits;
  if (!supports.empty())
    culprits.push_back(counted(supports.size(), "passive support ", "passive supports ") +
                       name_list(supports));
  if (!joints.empty())
    culprits.push_back(counted(joints.size(), "passive joint ", "passive joints ") +
                       name_list(joints));
  names_passive = !culprits.empty();
  std::ostringstream text;
  if (names_passive) {
    text << name_list(culprits, " and ")
         << (supports.size() + joints.size() == 1 ? " lets " : " let ") << (several ? "them" : "it")
         << " happen";
    if (!links.empty())
      text << "; " << subject << moves << " " << counted(links.size(), "link ", "links ")
           << name_list(links);
  } else {
    text << counted(links.size(), "link ", "links ") << name_list(links)
         << " can move without resistance";
  }
  if (effectors.empty())
    text << "; " << subject << moves << " no end effector "
         << (several ? kAcceptIdleMotionsHint : kAcceptIdleMotionHint);
  else
    text << (names_passive && !links.empty() ? " and" : "; " + std::string(subject) + moves)
         << " end effector" << (effectors.size() == 1 ? " " : "s ") << name_list(effectors);
  return text.str();
}

std::string describe_redundancy(const Model& model, const MatX& redundancies) {
  std::vector<std::string> links;
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const int from = 2 * static_cast<int>(l);
    const double change = redundancies.middleRows<6>(wrench_column(from)).norm() +
                          redundancies.middleRows<6>(wrench_column(from + 1)).norm();
    if (change > kNegligible * redundancies.norm())
      links.push_back("'" + model.links[l].name + "'");
  }
  std::ostringstream text;
  text << "the structure is over-constrained (" << redundancies.cols()
       << (redundancies.cols() == 1 ? " redundant constraint" : " redundant constraints")
       << "): a rigid model does not determine the internal wrenches in the loop through "
       << (links.size() == 1 ? "link " : "links ") << name_list(links)
       << "; they are reported as null";
  return text.str();
}

// The free motions, each said once: the parts that no support holds, then the motions of the
// supported part (in the basis of separated_motions; motions told alike share a line), then
// what stops them.
void describe_motions(const Model& model, const Topology& topology, const MatX& motions,
                      double length, std::vector<std::string>& lines) {
  const std::vector<int> part = unsupported_parts(topology);
  const std::vector<std::string> unsupported =
      describe_unsupported_parts(model, topology, part, length);
  lines.insert(lines.end(), unsupported.begin(), unsupported.end());

  // The motions that move a supported link end: a basis from the right singular vectors of
  // their rows there.
  MatX all = deflection_rows(motions, topology.end_count());
  for (Index row = 0; row < all.rows(); ++row)
    if (row % 6 >= 3) all.row(row) *= length;
  MatX supported = all;
  for (int end = 0; end < topology.end_count(); ++end)
    if (part[static_cast<std::size_t>(end)] >= 0) supported.middleRows<6>(6 * end).setZero();
  const Eigen::JacobiSVD<MatX> svd(supported, Eigen::ComputeThinV);
  Index count = 0;
  for (Index i = 0; i < svd.singularValues().size(); ++i)
    count += svd.singularValues()(i) > kTakesPart * all.norm();
  if (count == 0) return;
  const std::vector<PassiveConnection> passive = passive_connections(model, topology, part);
  const MatX basis = motions * svd.matrixV().leftCols(count);
  const MatX separated = separated_motions(basis, passive_motion_rows(passive, basis, length));

  // Motions told alike, in order of their first: their numbers and one of them.
  std::vector<std::pair<std::string, std::vector<Index>>> alike;
  bool passive_named = false;
  for (Index c = 0; c < count; ++c) {
    bool names_passive = false;
    std::string text = describe_motion(model, topology, passive, part, separated.col(c), length,
                                       false, names_passive);
    passive_named |= names_passive;
    auto same =
        std::find_if(alike.begin(), alike.end(), [&](const auto& a) { return a.first == text; });
    if (same == alike.end())
      alike.emplace_back(std::move(text), std::vector<Index>{c});
    else
      same->second.push_back(c);
  }
  for (const auto& [text, numbers] : alike) {
    if (numbers.size() == 1) {
      lines.push_back("free motion " + std::to_string(numbers.front() + 1) + ": " + text);
      continue;
    }
    std::vector<std::string> ordinals;
    for (const Index n : numbers) ordinals.push_back(std::to_string(n + 1));
    const std::string label = "free motions " + name_list(ordinals, " and ");
    bool names_passive = false;
    lines.push_back(label + ": " +
                    describe_motion(model, topology, passive, part, separated.col(numbers.front()),
                                    length, true, names_passive));
  }
  if (passive_named)
    lines.push_back(
        "to stop a free motion, give a joint or support that lets it happen a `stiffness:` "
        "(elastic) "
        "or `actuated: true` (a motor, locked where it stands)");
}

}  // namespace

#if STIFFMSA_HAVE_SUITESPARSE
namespace {
// The same from SuiteSparseQR's rank-revealing sparse QR, for systems too large for a dense
// decomposition: with Âᵀ = Q·R, the columns of Q past the rank span the null space of Â (and
// likewise from Â = Q·R for the left null space).
MatX trailing_q_columns(const SparseMatrix& m, Index& rank) {
  Eigen::SPQR<SparseMatrix> qr;
  qr.setPivotThreshold(kRankRevealingPivot);
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
    for (SparseMatrix::InnerIterator e(scaled, j); e; ++e)
      e.valueRef() *= scaling.row(e.row()) * scaling.column(j);
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
  lu.setThreshold(kRankRevealingPivot);
  if (lu.rank() == matrix.rows()) {
    spaces.right_equilibrated.resize(matrix.rows(), 0);
    spaces.left.resize(matrix.rows(), 0);
    return spaces;
  }
  spaces.right_equilibrated = Eigen::JacobiSVD<MatX>(lu.kernel(), Eigen::ComputeThinU).matrixU();
  Eigen::FullPivLU<MatX> lu_transposed(scaled.transpose());
  lu_transposed.setThreshold(kRankRevealingPivot);
  spaces.left = scaling.row.asDiagonal() * lu_transposed.kernel();
  return spaces;
}

SingularStructure analyse_singular_structure(const Model& model, const Topology& topology,
                                             const SparseMatrix& matrix) {
  SingularStructure s;
  const auto spaces = null_spaces(matrix);
  if (!spaces) {
    s.descriptions.push_back(
        "the system (" + std::to_string(matrix.rows()) +
        " unknowns) is singular: part of the structure can move freely or is over-constrained");
    return s;
  }
  s.analysed = true;
  if (spaces->right_equilibrated.cols() == 0) {
    s.descriptions.push_back(
        "the system is nearly singular (ill-conditioned) but has no exact free motion");
    return s;
  }
  const MatX& null_basis = spaces->right_equilibrated;
  s.left_null = spaces->left;

  // Split the null space: directions with a deflection part move something, the rest (the
  // null space of the deflection rows) change wrenches only.
  const MatX moving = deflection_rows(null_basis, topology.end_count());
  const Eigen::JacobiSVD<MatX> split(moving, Eigen::ComputeFullV);
  Index motion_count = 0;
  for (Index i = 0; i < split.singularValues().size(); ++i)
    motion_count += split.singularValues()(i) > kNegligible;
  const MatX v = split.matrixV();
  s.motions = spaces->column_scale.asDiagonal() * (null_basis * v.leftCols(motion_count));
  s.redundancies =
      spaces->column_scale.asDiagonal() * (null_basis * v.rightCols(v.cols() - motion_count));

  const double length = characteristic_length(model);
  if (motion_count > 0) describe_motions(model, topology, s.motions, length, s.descriptions);
  if (s.redundancies.cols() > 0)
    s.descriptions.push_back(describe_redundancy(model, s.redundancies));
  return s;
}

}  // namespace stiffmsa::detail
