#include "analysis/critical_load.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <map>
#include <span>
#include <sstream>

#include "analysis/cartesian.hpp"
#include "analysis/case_loads.hpp"
#include "assembly/assembler.hpp"
#include "elements/beam_element.hpp"
#include "elements/beam_geometric.hpp"
#include "elements/free_directions.hpp"
#include "elements/geometric_load_terms.hpp"
#include "solver/sparse_solver.hpp"
#include "solver/tree_solver.hpp"
#include "tolerances.hpp"

namespace stiffmsa::detail {

namespace {

// K_L's block from the deflection of link end `column_end` to the wrench at `row_end`.
struct LoadTerm {
  int row_end = 0, column_end = 0;
  Mat6 block;
};

void add_terms(const MatX& k, std::span<const int> ends, std::vector<LoadTerm>& terms) {
  for (std::size_t a = 0; a < ends.size(); ++a)
    for (std::size_t b = 0; b < ends.size(); ++b) {
      const Mat6 block = k.block<6, 6>(6 * static_cast<Index>(a), 6 * static_cast<Index>(b));
      if (!block.isZero(0)) terms.push_back({ends[a], ends[b], block});
    }
}

const Vec3& end_position(const Model& model, const Topology& topology, int end) {
  return model.points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(end)])]
      .position;
}

// The load-dependent stiffness of every link and joint at the linear solution; false where a
// wrench it needs is undetermined.
bool gather_load_terms(const Model& model, const Topology& topology, const Blocks& blocks,
                       const Result& result, const std::vector<Vec6>& external,
                       std::vector<LoadTerm>& terms) {
  std::vector<Vec6> wrench(static_cast<std::size_t>(topology.end_count()));
  terms.reserve(4 * model.links.size());
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const LinkResult& r = result.links[l];
    if (!r.from.wrench || !r.to.wrench) return false;
    wrench[2 * l] = *r.from.wrench;
    wrench[2 * l + 1] = *r.to.wrench;
  }
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const int from = 2 * static_cast<int>(l), to = from + 1;
    const int ends[] = {from, to};
    const Vec3 &p_from = end_position(model, topology, from),
               &p_to = end_position(model, topology, to);
    const Vec6 &w_from = wrench[static_cast<std::size_t>(from)],
               &w_to = wrench[static_cast<std::size_t>(to)];
    if (const auto* beam = std::get_if<BeamLink>(&model.links[l].kind)) {
      const double n = beam_axial_force(p_from, p_to, w_from.head<3>(), w_to.head<3>());
      if (n != 0) add_terms(beam_global_geometric_stiffness(*beam, p_from, p_to, n), ends, terms);
    } else if (!w_to.head<3>().isZero(0)) {
      add_terms(chord_load_stiffness(w_to.head<3>()), ends, terms);
    }
  }
  std::vector<Vec6> reactions;
  for (std::size_t g = 0; g < topology.groups.size(); ++g) {
    const ConnectionGroup& group = topology.groups[g];
    if (group.kind != ConnectionGroup::Kind::joint) continue;
    const FreeDirections* directions =
        blocks[static_cast<std::size_t>(topology.link_count) + g]->directions();
    if (!directions || directions->p == 0) continue;
    reactions.clear();
    for (int end : group.ends)
      reactions.push_back(wrench[static_cast<std::size_t>(end)] -
                          external[static_cast<std::size_t>(end)]);
    add_terms(joint_load_stiffness(*directions, reactions), group.ends, terms);
  }
  return true;
}

// The link end whose deflection stands for `end`'s, or −1 where it is held still: the ends of a
// weld (a rigid connection, a rigid or locked joint) move as one, and a unit wrench at any of
// them enters the same rows (theory.md §4.6); a rigid support's ends do not move.
int representative(const Topology& topology, const Blocks& blocks, int end) {
  const int g = topology.group_of_end[static_cast<std::size_t>(end)];
  const ConnectionGroup& group = topology.groups[static_cast<std::size_t>(g)];
  const FreeDirections* directions =
      blocks[static_cast<std::size_t>(topology.link_count + g)]->directions();
  const bool welded =
      group.kind == ConnectionGroup::Kind::rigid_connection ||
      (group.kind == ConnectionGroup::Kind::joint && directions && directions->p == 0);
  if (group.kind == ConnectionGroup::Kind::support && directions && directions->p == 0) return -1;
  return welded ? group.ends.front() : end;
}

std::string bending_phrase(double about_y, double about_z, double twist, bool plural) {
  const double largest = std::max({about_y, about_z, twist});
  const bool y = about_y >= 0.5 * largest, z = about_z >= 0.5 * largest, t = twist >= 0.5 * largest;
  std::string text;
  if (y || z) {
    text = plural ? "bend about their local " : "bends about its local ";
    text += y && z ? "y and z axes" : (y ? "y axis" : "z axis");
  }
  if (t) text += (text.empty() ? "" : " and ") + std::string(plural ? "twist" : "twists");
  return text;
}

std::string motion_phrase(double rotation, double slide, bool plural) {
  const double largest = std::max(rotation, slide);
  const bool r = rotation >= 0.5 * largest, s = slide >= 0.5 * largest;
  if (r && s) return plural ? "rotate and slide" : "rotates and slides";
  return r ? (plural ? "rotate" : "rotates") : (plural ? "slide" : "slides");
}

// The parts of a mode that move most, in the user's terms; their phrases are made only for the
// parts the description names.
struct ModePart {
  double size = 0;
  const char* kind = "";              // "link", "joint", "support"
  const std::string* name = nullptr;  // the user's
  bool bends = false;                 // a link: amounts about_y, about_z, twist
  double amounts[3] = {0, 0, 0};      // else a joint or support: rotation, slide
  double rank = 0;                    // the size in steps of kModeTie of the largest
  std::string phrase(bool plural) const {
    return bends ? bending_phrase(amounts[0], amounts[1], amounts[2], plural)
                 : motion_phrase(amounts[0], amounts[1], plural);
  }
};

std::optional<Vec3> link_zref(const LinkKind& kind) {
  if (const auto* beam = std::get_if<BeamLink>(&kind)) return beam->zref;
  if (const auto* matrix = std::get_if<MatrixLink>(&kind)) return matrix->zref;
  if (const auto* compliance = std::get_if<ComplianceLink>(&kind)) return compliance->zref;
  return std::nullopt;
}

// Which links bend (their end rotations against their chord's, local axes) and which joints and
// elastic supports move along their free directions (slides weighed by the model's size), for
// a mode's deflections x: those within kModeShare of the largest, largest first, three names
// to a phrase.
std::string describe_mode(const Model& model, const Topology& topology, const Blocks& blocks,
                          const VecX& x) {
  const double length = characteristic_length(model);
  std::vector<ModePart> parts;
  auto deflection = [&](int end) -> Vec6 { return x.segment<6>(deflection_column(end)); };
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    if (std::holds_alternative<RigidLink>(model.links[l].kind)) continue;
    const int from = 2 * static_cast<int>(l), to = from + 1;
    const Vec3 &p_from = end_position(model, topology, from),
               &p_to = end_position(model, topology, to);
    const Mat3 axes = link_axes(p_from, p_to, link_zref(model.links[l].kind));
    const double span = (p_to - p_from).norm();
    const Vec6 d_from = deflection(from), d_to = deflection(to);
    const Vec3 move_from = axes * d_from.head<3>(), move_to = axes * d_to.head<3>();
    const Vec3 turn_from = axes * d_from.tail<3>(), turn_to = axes * d_to.tail<3>();
    const double chord_z = (move_to.y() - move_from.y()) / span;
    const double chord_y = -(move_to.z() - move_from.z()) / span;
    const double about_z =
        std::max(std::abs(turn_from.z() - chord_z), std::abs(turn_to.z() - chord_z));
    const double about_y =
        std::max(std::abs(turn_from.y() - chord_y), std::abs(turn_to.y() - chord_y));
    const double twist = std::abs(turn_to.x() - turn_from.x());
    const double size = std::max({about_y, about_z, twist});
    if (size > 0)
      parts.push_back({size, "link", &model.links[l].name, true, {about_y, about_z, twist}});
  }
  for (std::size_t g = 0; g < topology.groups.size(); ++g) {
    const ConnectionGroup& group = topology.groups[g];
    const bool joint = group.kind == ConnectionGroup::Kind::joint;
    if (!joint && group.kind != ConnectionGroup::Kind::support) continue;
    const FreeDirections* directions =
        blocks[static_cast<std::size_t>(topology.link_count) + g]->directions();
    if (!directions || directions->p == 0) continue;
    const MatX free = directions->free();
    const Mat6 projection = free.transpose() * directions->gram().ldlt().solve(free);
    double rotation = 0, slide = 0;
    const Vec6 first = deflection(group.ends.front());
    if (joint) {
      for (std::size_t k = 1; k < group.ends.size(); ++k) {
        const Vec6 along = projection * (deflection(group.ends[k]) - first);
        rotation = std::max(rotation, along.tail<3>().norm());
        slide = std::max(slide, along.head<3>().norm() / length);
      }
    } else {
      const Vec6 along = projection * first;
      rotation = along.tail<3>().norm();
      slide = along.head<3>().norm() / length;
    }
    const double size = std::max(rotation, slide);
    const std::string& name = joint ? model.joints[static_cast<std::size_t>(group.source)].name
                                    : model.supports[static_cast<std::size_t>(group.source)].name;
    if (size > 0)
      parts.push_back({size, joint ? "joint" : "support", &name, false, {rotation, slide}});
  }
  if (parts.empty()) return "";
  // Sizes that agree to kModeTie of the largest are equal — a symmetric structure's mirror
  // parts, which rounding would otherwise order — and keep the model's order.
  const double largest =
      std::max_element(parts.begin(), parts.end(), [](const ModePart& a, const ModePart& b) {
        return a.size < b.size;
      })->size;
  for (ModePart& part : parts) part.rank = std::round(part.size / largest / kModeTie);
  std::stable_sort(parts.begin(), parts.end(),
                   [](const ModePart& a, const ModePart& b) { return a.rank > b.rank; });
  // Phrases in the order of their largest part; the parts of each in order of size.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ModePart*>> by_phrase;
  for (const ModePart& part : parts) {
    if (part.size < kModeShare * largest) break;
    const std::string key = part.kind + ("|" + part.phrase(false));
    if (!by_phrase.count(key)) order.push_back(key);
    by_phrase[key].push_back(&part);
  }
  // A frame's mode has many parts: the three largest phrases say where it is.
  constexpr std::size_t kPhrases = 3;
  if (order.size() > kPhrases) order.resize(kPhrases);
  std::ostringstream text;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::vector<const ModePart*>& group = by_phrase[order[i]];
    if (i > 0) text << "; ";
    if (group.size() == 1) {
      text << group.front()->kind << " '" << *group.front()->name << "' "
           << group.front()->phrase(false);
      continue;
    }
    text << group.front()->kind << "s ";
    constexpr std::size_t kNamed = 3;
    const std::size_t named = std::min(group.size(), kNamed);
    for (std::size_t k = 0; k < named; ++k) {
      if (k > 0) text << (k + 1 == named && group.size() <= kNamed ? " and " : ", ");
      text << '\'' << *group[k]->name << '\'';
    }
    if (group.size() > kNamed) text << " and " << group.size() - kNamed << " more";
    text << ' ' << group.front()->phrase(true);
  }
  return text.str();
}

// The eigenvalue μ = 1/λ of the critical load and its vector; `converged` false where an
// iteration stopped at its last estimate.
struct RightmostEigen {
  double value = 0;
  VecX vector;
  bool converged = true;
};

// The largest real positive eigenvalue among `values`: real within kRealEigenvalue, positive
// beyond kLeastLoadEigenvalue of the largest magnitude; none where there is none.
std::optional<Index> rightmost_real(const Eigen::VectorXcd& values) {
  if (values.size() == 0) return std::nullopt;
  const double largest = values.cwiseAbs().maxCoeff();
  std::optional<Index> best;
  for (Index i = 0; i < values.size(); ++i) {
    const double re = values(i).real(), im = values(i).imag();
    if (!(re > kLeastLoadEigenvalue * largest) || std::abs(im) > kRealEigenvalue * std::abs(re))
      continue;
    if (!best || re > values(*best).real()) best = i;
  }
  return best;
}

// The rightmost real positive eigenvalue of the n×n operator `apply` by Arnoldi's method: the
// Krylov space of a fixed start vector (the operator applied to a smooth vector, so that it lies
// in the operator's range) is grown, orthogonalised twice by Gram–Schmidt, and the Ritz values of
// its Hessenberg matrix are checked every 10 steps; the pair is taken where its residual
// h_{j+1,j}·|y_j| is below kArnoldiTolerance of the largest Ritz value, or where the space is
// invariant. At most kMostArnoldiSteps steps; then the last estimate, not converged. The
// rightmost eigenvalue is an extreme point of the spectrum, which Krylov spaces find first.
std::optional<RightmostEigen> rightmost_by_arnoldi(const std::function<VecX(const VecX&)>& apply,
                                                   Index n) {
  const Index most = std::min<Index>(n, kMostArnoldiSteps);
  VecX start(n);
  for (Index i = 0; i < n; ++i) start(i) = 1.0 + 0.5 * std::sin(0.7 * static_cast<double>(i));
  start = apply(start);
  if (!(start.norm() > 0)) return std::nullopt;
  MatX basis(n, most + 1);
  MatX hessenberg = MatX::Zero(most + 1, most);
  basis.col(0) = start.normalized();
  std::optional<RightmostEigen> estimate;
  for (Index j = 0; j < most; ++j) {
    VecX w = apply(basis.col(j));
    const double applied = w.norm();
    for (int pass = 0; pass < 2; ++pass) {
      const VecX c = basis.leftCols(j + 1).transpose() * w;
      w -= basis.leftCols(j + 1) * c;
      hessenberg.col(j).head(j + 1) += c;
    }
    hessenberg(j + 1, j) = w.norm();
    const Index steps = j + 1;
    const bool invariant = !(hessenberg(j + 1, j) > kArnoldiTolerance * applied);
    if (!invariant) basis.col(j + 1) = w / hessenberg(j + 1, j);
    if (!invariant && steps % 10 != 0 && steps != most) continue;
    Eigen::EigenSolver<MatX> ritz(hessenberg.topLeftCorner(steps, steps), true);
    const std::optional<Index> best = rightmost_real(ritz.eigenvalues());
    if (!best) {
      if (invariant) return std::nullopt;
      continue;
    }
    const VecX y = ritz.eigenvectors().col(*best).real().normalized();
    const double value = ritz.eigenvalues()(*best).real();
    const double residual = std::abs(hessenberg(j + 1, j) * y(steps - 1));
    const bool converged =
        invariant || residual <= kArnoldiTolerance * ritz.eigenvalues().cwiseAbs().maxCoeff();
    estimate = RightmostEigen{value, basis.leftCols(steps) * y, converged};
    if (converged || invariant) return estimate;
  }
  return estimate;
}

// The unloaded structure's deflections and wrenches under wrenches at link ends, a column per
// load: by the tree solve's passes where the linear solve takes them (the solver `auto`, links
// and connections forming a tree), else from one factorisation of the assembled mixed system
// with the solver asked for. The passes cost a few 6×6 products per link end and column and
// factorise nothing; their solution is checked against every block's equations in one column,
// the sum of the columns weighed alike, as the linear solve checks its own.
class UnloadedSolves {
 public:
  // `reuse`: the workspace's tree order, buffers and the linear solve's cut system, or nulls.
  UnloadedSolves(const Topology& topology, const Blocks& blocks, const SolveOptions& options,
                 const CriticalLoadReuse& reuse)
      : topology_(topology),
        blocks_(blocks),
        options_(options),
        scratch_(reuse.scratch ? *reuse.scratch : own_scratch_),
        cut_system_(reuse.cut_system) {
    const TreeOrder* tree = reuse.tree;
    if (options.solver != SolverKind::automatic || !passes_tree(blocks)) return;
    if (!tree) {
      own_tree_ = tree_order(topology);
      if (own_tree_) tree = &*own_tree_;
    }
    tree_ = tree;
  }
  // A long model's buffers are not kept in the workspace.
  ~UnloadedSolves() { scratch_.release_large(); }
  UnloadedSolves(const UnloadedSolves&) = delete;
  UnloadedSolves& operator=(const UnloadedSolves&) = delete;

  // The wrenches of a solve, a column per load (no preload: these are no load case); fill with
  // external().add, then solve.
  EndWrenches& external(Index columns) {
    external_.reset(topology_.end_count(), columns, 0);
    return external_;
  }

  // Every unknown (the mixed system's layout) under each column of external(); nullopt where
  // the system is singular.
  std::optional<MatX> solve() {
    if (tree_) {
      if (std::optional<MatX> x = solve_on_tree()) return x;
      tree_ = nullptr;  // too many cuts, or ill-conditioned: the factorising solve decides
    }
    if (!system_ && !factorise()) return std::nullopt;
    MatX rhs = MatX::Zero(topology_.unknowns(), external_.columns());
    VecX column(topology_.unknowns());
    for (Index c = 0; c < external_.columns(); ++c) {
      column.setZero();
      for (int end = 0; end < topology_.end_count(); ++end)
        if (external_.any_at(end) && !external_.at(end).col(c).isZero(0))
          assembler_->add_wrench(blocks_, topology_, end, external_.at(end).col(c), column);
      rhs.col(c) = column;
    }
    double solve_residual = 0;
    MatX x = system_->solve(std::move(rhs), options_.refinement_steps, solve_residual);
    residual_ = std::max(residual_, solve_residual);
    return x;
  }

  // The largest relative residual of the solves so far.
  double residual() const { return residual_; }

 private:
  std::optional<MatX> solve_on_tree() {
    if (cut_system_) {
      if (tree_solve_with_cut_system_of(*cut_system_, blocks_, topology_, *tree_, external_,
                                        scratch_))
        if (std::optional<MatX> x = checked_tree_solution()) return x;
      cut_system_ = nullptr;  // not this model's cut system after all: the tree solve's own
    }
    if (!tree_solve(blocks_, topology_, *tree_, external_, 1 / options_.warn_condition, scratch_))
      return std::nullopt;
    return checked_tree_solution();
  }

  // scratch_.x where it passes the check, as the linear solve's.
  std::optional<MatX> checked_tree_solution() {
    // The check's one column: every column weighed, with weights that no cancellation of like
    // columns hides.
    const Index columns = external_.columns();
    VecX weights(columns);
    for (Index c = 0; c < columns; ++c) weights(c) = 1.0 + 1.0 / static_cast<double>(c % 7 + 1);
    check_x_ = scratch_.x * weights;
    check_external_.reset(topology_.end_count(), 1, 0);
    for (int end = 0; end < topology_.end_count(); ++end)
      if (external_.any_at(end)) check_external_.add(end, 0, external_.at(end) * weights);
    const BlockCheck check =
        check_block_by_block(blocks_, topology_, check_x_, check_external_, scratch_);
    if (!(check.relative_residual <= options_.max_relative_residual)) return std::nullopt;
    residual_ = std::max(residual_, check.relative_residual);
    return MatX(scratch_.x);
  }

  bool factorise() {
    assembler_ = std::make_unique<Assembler>(blocks_, topology_.unknowns());
    assembler_->fill(blocks_, matrix_);
    system_ = std::make_unique<FactorizedSystem>(options_.solver);
    if (system_->factorize(matrix_, options_.singular_rcond)) return true;
    system_.reset();
    return false;
  }

  const Topology& topology_;
  const Blocks& blocks_;
  const SolveOptions& options_;
  std::optional<TreeOrder> own_tree_;
  const TreeOrder* tree_ = nullptr;
  TreeScratch own_scratch_;
  TreeScratch& scratch_;
  const TreeScratch* cut_system_ = nullptr;
  EndWrenches external_, check_external_;
  RowMajorMatX check_x_;
  std::unique_ptr<Assembler> assembler_;
  SparseMatrix matrix_;
  std::unique_ptr<FactorizedSystem> system_;
  double residual_ = 0;
};

// K_L where it lives: at each node, an orthonormal basis Q_i of the wrenches its load terms
// give there (the range of its block row, at most 6 directions; fewer where the terms are of
// low rank: a joint's along its free directions, a lever's across its force), so that
// K_L = U·Uᵀ·K_L, U = diag(Q_i).
struct LoadDirections {
  std::vector<Index> first;  // per node: its first column of U
  std::vector<MatX> basis;   // per node: Q_i, 6 × r_i
  Index count = 0;           // r, the columns of U
};

// `blocks`: K_L's blocks (row node, column node), in the eigenproblem's units. A direction of a
// node's block row below kLoadTermRank of its largest column is rounding of a zero (a local zero
// row turned to global axes) and is left out.
LoadDirections load_directions(Index nodes,
                               const std::vector<std::pair<std::pair<int, int>, Mat6>>& blocks) {
  std::vector<std::vector<const Mat6*>> rows(static_cast<std::size_t>(nodes));
  for (const auto& [at, block] : blocks) rows[static_cast<std::size_t>(at.first)].push_back(&block);
  LoadDirections directions;
  directions.first.resize(static_cast<std::size_t>(nodes));
  directions.basis.resize(static_cast<std::size_t>(nodes));
  Eigen::Matrix<double, 6, Eigen::Dynamic> rest;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    directions.first[i] = directions.count;
    if (rows[i].empty()) continue;
    // Gram–Schmidt with column pivoting on the block row's columns: the largest column left
    // becomes the next direction (orthogonalised twice against the ones before), and is taken
    // out of every column; until the largest left is below kLoadTermRank of the first.
    rest.resize(6, 6 * static_cast<Index>(rows[i].size()));
    for (std::size_t b = 0; b < rows[i].size(); ++b)
      rest.middleCols<6>(6 * static_cast<Index>(b)) = *rows[i][b];
    Mat6 basis;
    Index rank = 0;
    double first = 0;
    for (; rank < 6; ++rank) {
      Index largest = 0;
      const double norm = std::sqrt(rest.colwise().squaredNorm().maxCoeff(&largest));
      if (rank == 0) first = norm;
      if (!(norm > kLoadTermRank * first)) break;
      Vec6 q = rest.col(largest) / norm;
      for (int pass = 0; pass < 2; ++pass) {
        q -= basis.leftCols(rank) * (basis.leftCols(rank).transpose() * q);
        q.normalize();
      }
      basis.col(rank) = q;
      rest -= q * (q.transpose() * rest);
    }
    directions.basis[i] = basis.leftCols(rank);
    directions.count += rank;
  }
  return directions;
}

// The eigenvector of `a` for its eigenvalue `value`, by inverse iteration: two solves with
// a − value·I, from a fixed smooth vector (so that the results repeat). The shift is moved off
// the eigenvalue by a rounding-sized step so that the factors stay finite; the iteration then
// gains about the ratio of that step to the next eigenvalue's distance per solve.
VecX eigenvector_by_inverse_iteration(const MatX& a, double value) {
  const Index r = a.rows();
  const double step = kInverseIterationShift * std::max(std::abs(value), a.cwiseAbs().maxCoeff());
  const Eigen::PartialPivLU<MatX> lu(a - (value + step) * MatX::Identity(r, r));
  VecX v(r);
  for (Index i = 0; i < r; ++i) v(i) = 1.0 + 0.5 * std::sin(0.7 * static_cast<double>(i));
  for (int pass = 0; pass < 2; ++pass) v = lu.solve(v).normalized();
  return v;
}

// The rightmost real positive eigenvalue of the r×r matrix a = −Z·F·U and its vector. a has
// the rank of F·U at most, the structure's flexible directions the load directions reach (a
// serial robot's joints and beams, whatever the number of its link ends): an LU with complete
// pivoting P·a·Q = L·U, stopped at pivots below kLoadTermRank of the first, gives
// a = X·Y, X = P⁻¹·L_ρ, Y = U_ρ·Q⁻¹, whose nonzero eigenvalues are those of the ρ×ρ matrix
// Y·X (Y·X·y = μ·y gives a·X·y = μ·X·y). Every eigenvalue of the small matrix (eigenvalues_of:
// Hessenberg form and the QR iteration, no vectors), then the one vector by inverse iteration.
std::optional<RightmostEigen> rightmost_of_low_rank(const MatX& a) {
  // Gaussian elimination with complete pivoting, stopped where the largest entry left is below
  // kLoadTermRank of the first pivot: then P·a·Q = L_ρ·U_ρ to that fraction.
  const Index r = a.rows();
  if (!a.allFinite()) return std::nullopt;
  MatX m = a;
  std::vector<Index> row_order(static_cast<std::size_t>(r)), column_order(row_order.size());
  for (Index i = 0; i < r; ++i) row_order[static_cast<std::size_t>(i)] = i;
  column_order = row_order;
  Index rank = 0;
  double first_pivot = 0;
  for (; rank < r; ++rank) {
    // The largest entry left, the first of its size column by column: each column's largest
    // (a vectorised pass), then its row in the column that holds it.
    Index pivot_row = rank, pivot_column = rank;
    double pivot = -1;
    for (Index j = rank; j < r; ++j) {
      const double largest = m.col(j).tail(r - rank).cwiseAbs().maxCoeff();
      if (largest > pivot) {
        pivot = largest;
        pivot_column = j;
      }
    }
    if (!(pivot >= 0)) break;  // every entry left is NaN: no rank beyond this
    while (pivot_row + 1 < r && std::abs(m(pivot_row, pivot_column)) != pivot) ++pivot_row;
    if (rank == 0) first_pivot = pivot;
    if (!(pivot > kLoadTermRank * first_pivot)) break;
    m.row(rank).swap(m.row(pivot_row));
    m.col(rank).swap(m.col(pivot_column));
    std::swap(row_order[static_cast<std::size_t>(rank)],
              row_order[static_cast<std::size_t>(pivot_row)]);
    std::swap(column_order[static_cast<std::size_t>(rank)],
              column_order[static_cast<std::size_t>(pivot_column)]);
    const Index rest = r - rank - 1;
    m.col(rank).tail(rest) /= m(rank, rank);
    m.bottomRightCorner(rest, rest).noalias() -= m.col(rank).tail(rest) * m.row(rank).tail(rest);
  }
  if (rank == 0) return std::nullopt;
  // a = X·Y, X = P⁻¹·L_ρ (r×ρ), Y = U_ρ·Q⁻¹ (ρ×r): the eigenvalues of Y·X.
  MatX x = MatX::Zero(r, rank), y = MatX::Zero(rank, r);
  for (Index i = 0; i < r; ++i) {
    const Index row = row_order[static_cast<std::size_t>(i)];
    const Index column = column_order[static_cast<std::size_t>(i)];
    for (Index k = 0; k < std::min(i, rank); ++k) x(row, k) = m(i, k);
    if (i < rank) x(row, i) = 1;
    for (Index k = 0; k <= std::min(i, rank - 1); ++k) y(k, column) = m(k, i);
  }
  const MatX small = y * x;
  const Eigen::VectorXcd values = eigenvalues_of(small).values;
  const std::optional<Index> best = rightmost_real(values);
  if (!best) return std::nullopt;
  const double value = values(*best).real();
  return RightmostEigen{value, x * eigenvector_by_inverse_iteration(small, value), true};
}

// The eigenvalues of the 2×2 matrix [a b; c d]: d + x for the roots x of x² − 2p·x − b·c,
// p = (a − d)/2; the larger real root first, the other from their product −b·c (no
// cancellation).
void eigenvalues_of_2x2(double a, double b, double c, double d, std::complex<double>& first,
                        std::complex<double>& second) {
  const double p = 0.5 * (a - d);
  const double discriminant = p * p + b * c;
  if (discriminant >= 0) {
    const double root = std::sqrt(discriminant);
    const double x = p >= 0 ? p + root : p - root;
    first = d + x;
    second = x != 0 ? d - b * c / x : d;
  } else {
    const double root = std::sqrt(-discriminant);
    first = {d + p, root};
    second = {d + p, -root};
  }
}

// The Householder reflection P = I − τ·v·vᵀ, v = (1, v1[, v2]), with P·u = β·e₁ for the vector u
// it was made from (β of the sign opposite to u's first entry, so that nothing cancels); the
// identity (τ = 0) where u is zero.
struct Reflection {
  double tau = 0, v1 = 0, v2 = 0, beta = 0;
  static Reflection of(double u0, double u1, double u2) {
    Reflection r;
    const double norm = std::sqrt(u0 * u0 + u1 * u1 + u2 * u2);
    if (norm == 0) return r;
    r.beta = u0 >= 0 ? -norm : norm;
    r.tau = (r.beta - u0) / r.beta;
    r.v1 = u1 / (u0 - r.beta);
    r.v2 = u2 / (u0 - r.beta);
    return r;
  }
};

// h ← P·h·P on the window h[lo..hi, lo..hi] for the reflection P of rows and columns
// k..k + kRows − 1 (kRows = 3 or 2); the columns left of k − 1 hold zeros in those rows, the rows
// below k + 3 zeros in those columns.
template <int kRows>
void reflect_in_window(MatX& h, const Reflection& p, Index k, Index lo, Index hi) {
  const Index stride = h.rows();
  for (Index j = std::max(lo, k - 1); j <= hi; ++j) {
    double* c = h.data() + j * stride + k;
    double d = c[0] + p.v1 * c[1];
    if constexpr (kRows == 3) d += p.v2 * c[2];
    d *= p.tau;
    c[0] -= d;
    c[1] -= d * p.v1;
    if constexpr (kRows == 3) c[2] -= d * p.v2;
  }
  if (k > lo) {  // the bulge's column, now (β, 0[, 0]) but for rounding
    h(k, k - 1) = p.beta;
    h(k + 1, k - 1) = 0;
    if constexpr (kRows == 3) h(k + 2, k - 1) = 0;
  }
  double* c0 = h.data() + k * stride;
  double* c1 = c0 + stride;
  double* c2 = c1 + stride;
  const Index last_row = std::min(k + 3, hi);
  for (Index i = lo; i <= last_row; ++i) {
    double d = c0[i] + p.v1 * c1[i];
    if constexpr (kRows == 3) d += p.v2 * c2[i];
    d *= p.tau;
    c0[i] -= d;
    c1[i] -= d * p.v1;
    if constexpr (kRows == 3) c2[i] -= d * p.v2;
  }
}

// One Francis double-shift sweep on the unreduced Hessenberg window h[lo..hi, lo..hi]
// (hi − lo ≥ 2), the shifts being the roots of z² − s·z + t: a bulge made in the first column of
// (H − z₁)(H − z₂) and chased down by 3-vector reflections, the last a 2-vector one. Only the
// window changes: the entries beside it do not change its eigenvalues.
void francis_sweep(MatX& h, Index lo, Index hi, double s, double t) {
  double x = h(lo, lo) * h(lo, lo) + h(lo, lo + 1) * h(lo + 1, lo) - s * h(lo, lo) + t;
  double y = h(lo + 1, lo) * (h(lo, lo) + h(lo + 1, lo + 1) - s);
  double z = h(lo + 1, lo) * h(lo + 2, lo + 1);
  for (Index k = lo; k + 1 < hi; ++k) {
    const Reflection p = Reflection::of(x, y, z);
    if (p.tau != 0) reflect_in_window<3>(h, p, k, lo, hi);
    x = h(k + 1, k);
    y = h(k + 2, k);
    if (k + 3 <= hi) z = h(k + 3, k);
  }
  const Reflection p = Reflection::of(x, y, 0.0);  // rows hi − 1 and hi
  if (p.tau != 0) reflect_in_window<2>(h, p, hi - 1, lo, hi);
}

// `a` (scaled to a largest entry of 1) to upper Hessenberg form in place, by a Householder
// reflection per column from both sides; `v` and `w` are buffers.
void to_hessenberg(MatX& a, VecX& v, VecX& w) {
  const Index n = a.rows();
  v.resize(n);
  w.resize(n);
  for (Index k = 0; k + 2 < n; ++k) {
    const Index m = n - k - 1;  // the entries below the diagonal in column k
    const double tail = a.col(k).segment(k + 2, m - 1).squaredNorm();
    if (tail == 0) continue;
    const double x0 = a(k + 1, k);
    const double norm = std::sqrt(x0 * x0 + tail);
    const double beta = x0 >= 0 ? -norm : norm;
    const double tau = (beta - x0) / beta;
    v.head(m) = a.col(k).segment(k + 1, m) / (x0 - beta);
    v(0) = 1;
    a(k + 1, k) = beta;
    a.col(k).segment(k + 2, m - 1).setZero();
    for (Index j = k + 1; j < n; ++j) {
      auto column = a.col(j).segment(k + 1, m);
      column -= (tau * v.head(m).dot(column)) * v.head(m);
    }
    // a ← a·P: w = τ·a·v by columns, then a's columns k + 1.. less w·vᵀ.
    w.setZero();
    for (Index c = 0; c < m; ++c) w += a.col(k + 1 + c) * v(c);
    w *= tau;
    for (Index c = 0; c < m; ++c) a.col(k + 1 + c) -= w * v(c);
  }
}

}  // namespace

Eigenvalues eigenvalues_of(MatX a) {
  const Index n = a.rows();
  Eigenvalues found{Eigen::VectorXcd::Zero(n)};
  Eigen::VectorXcd& values = found.values;
  // A NaN would slip past the largest-entry test below and cost every sweep: none are found
  // (no eigenvalue, so no factor), as where Eigen's own iteration fails.
  if (!a.allFinite()) return {};
  const double scale = n > 0 ? a.cwiseAbs().maxCoeff() : 0.0;
  if (scale == 0) return found;
  a /= scale;
  const MatX original = a;
  VecX v, w;
  to_hessenberg(a, v, w);
  MatX& h = a;
  const int most_sweeps = kMostQrSweepsPerEigenvalue * static_cast<int>(n);
  int sweeps = 0, since_split = 0;
  for (Index hi = n - 1; hi >= 0;) {
    // The window: the rows up from hi whose subdiagonal entries are not (yet) negligible. The
    // matrix's largest entry is 1: where both neighbours are zero, a subdiagonal entry is
    // weighed against it.
    Index lo = hi;
    for (; lo > 0; --lo) {
      const double beside = std::abs(h(lo - 1, lo - 1)) + std::abs(h(lo, lo));
      if (std::abs(h(lo, lo - 1)) <= kQrSplit * (beside > 0 ? beside : 1.0)) {
        h(lo, lo - 1) = 0;
        break;
      }
    }
    if (lo == hi) {
      values(hi) = h(hi, hi) * scale;
      hi -= 1;
      since_split = 0;
      continue;
    }
    if (lo + 1 == hi) {
      eigenvalues_of_2x2(h(lo, lo), h(lo, hi), h(hi, lo), h(hi, hi), values(lo), values(hi));
      values(lo) *= scale;
      values(hi) *= scale;
      hi -= 2;
      since_split = 0;
      continue;
    }
    if (++sweeps > most_sweeps) {
      const Eigen::EigenSolver<MatX> fallback(original, false);
      if (fallback.info() != Eigen::Success) return {Eigen::VectorXcd(), true};
      return {fallback.eigenvalues() * scale, true};
    }
    // The shifts: the trailing 2×2 block's eigenvalues (their sum and product); every
    // kQrExceptionalShiftEvery sweeps without a split, to leave a cycle, LAPACK's exceptional
    // pair instead: d + x for the roots x of x² − kQrExceptionalShiftSum·size·x + size², d the
    // trailing diagonal entry and size the trailing subdiagonal's. Centred at d, not at 0, they
    // move a matrix whose spectrum is far from 0 (near 1000·I, say) as much as one near 0.
    double s = h(hi - 1, hi - 1) + h(hi, hi);
    double t = h(hi - 1, hi - 1) * h(hi, hi) - h(hi - 1, hi) * h(hi, hi - 1);
    if (++since_split % kQrExceptionalShiftEvery == 0) {
      const double size = std::abs(h(hi, hi - 1)) + std::abs(h(hi - 1, hi - 2));
      const double d = h(hi, hi);
      s = 2 * d + kQrExceptionalShiftSum * size;
      t = d * (d + kQrExceptionalShiftSum * size) + size * size;
    }
    francis_sweep(h, lo, hi, s, t);
  }
  return found;
}

std::vector<Vec6> loads_at_ends(const Model& model, const Topology& topology) {
  std::vector<Vec6> external(static_cast<std::size_t>(topology.end_count()), Vec6::Zero());
  for (std::size_t i = 0; i < model.loads.size(); ++i)
    external[static_cast<std::size_t>(topology.load_ends[i])] += model.loads[i].wrench;
  return external;
}

CriticalLoad critical_load(const Model& model, const Topology& topology,
                           const std::vector<SpinLock>& locks, const SolveOptions& options,
                           const Result& result, const std::vector<Vec6>& end_loads,
                           std::vector<std::string>& notes, EigenMethod method,
                           const CriticalLoadReuse& reuse) {
  Blocks own_blocks;
  if (!reuse.blocks) own_blocks = make_blocks(model, topology, locks);
  const Blocks& blocks = reuse.blocks ? *reuse.blocks : own_blocks;
  std::vector<LoadTerm> terms;
  if (!gather_load_terms(model, topology, blocks, result, end_loads, terms)) {
    notes.push_back(
        "the critical load factor is not found: some link end's wrench under the loads is "
        "undetermined");
    return {};
  }
  // The link ends the load terms act at and from, one per set of ends that move as one.
  std::vector<int> node_of_end(static_cast<std::size_t>(topology.end_count()), -1);
  std::vector<int> node_ends;  // the representative end of each node
  auto node = [&](int end) {
    const int r = representative(topology, blocks, end);
    if (r < 0) return -1;
    int& n = node_of_end[static_cast<std::size_t>(r)];
    if (n < 0) {
      n = static_cast<int>(node_ends.size());
      node_ends.push_back(r);
    }
    return n;
  };
  // K_L's blocks between nodes, in units where rotations are weighed by the model's size ℓ
  // (S⁻¹·K_L·S⁻¹, S = diag(1, 1, 1, ℓ, ℓ, ℓ) per node), so that every entry of the eigenproblem
  // is a pure number of like size: its eigenvalues are the same.
  const double length = characteristic_length(model);
  Vec6 weight = Vec6::Ones();
  weight.tail<3>().setConstant(length);
  std::vector<std::pair<std::pair<int, int>, Mat6>> placed;
  placed.reserve(terms.size());
  for (const LoadTerm& term : terms) {
    const int row = node(term.row_end), column = node(term.column_end);
    if (row >= 0 && column >= 0)
      placed.push_back(
          {{row, column},
           weight.cwiseInverse().asDiagonal() * term.block * weight.cwiseInverse().asDiagonal()});
  }
  if (placed.empty()) return {};
  const Index nodes = static_cast<Index>(node_ends.size()), n = 6 * nodes;

  // The eigenproblem Δt = F·(−λ·K_L·Δt), F the nodes' deflections under unit wrenches at the
  // nodes: the eigenvalues μ = 1/λ of −F·K_L. The constraint rows' infinite λ are μ = 0 here,
  // below kLeastLoadEigenvalue of the largest |μ|.
  UnloadedSolves solves(topology, blocks, options, reuse);
  const LoadDirections directions = load_directions(nodes, placed);
  const Index r = directions.count;
  std::optional<RightmostEigen> rightmost;
  MatX unknowns_per_direction;  // the dense way: every unknown under each column of S·U
  bool singular = false;
  if (method == EigenMethod::dense ||
      (method == EigenMethod::automatic && r <= kMostDenseNodes * 6)) {
    // K_L = U·Z, Z = Uᵀ·K_L: the nonzero eigenvalues of −F·U·Z are those of the r×r matrix
    // −Z·(F·U), and F·U takes r solves, a unit wrench along each direction of U.
    EndWrenches& external = solves.external(r);
    for (Index i = 0; i < nodes; ++i) {
      const MatX& basis = directions.basis[static_cast<std::size_t>(i)];
      for (Index c = 0; c < basis.cols(); ++c)
        external.add(node_ends[static_cast<std::size_t>(i)],
                     directions.first[static_cast<std::size_t>(i)] + c,
                     weight.asDiagonal() * basis.col(c));
    }
    std::optional<MatX> x = solves.solve();
    if (!x) {
      singular = true;
    } else {
      unknowns_per_direction = std::move(*x);
      // F·U at the nodes, in the eigenproblem's units.
      MatX flexibility(n, r);
      for (Index k = 0; k < nodes; ++k)
        flexibility.middleRows<6>(6 * k) =
            weight.asDiagonal() * unknowns_per_direction.middleRows<6>(
                                      deflection_column(node_ends[static_cast<std::size_t>(k)]));
      MatX reduced = MatX::Zero(r, r);
      for (const auto& [at, block] : placed) {
        const MatX& basis = directions.basis[static_cast<std::size_t>(at.first)];
        if (basis.cols() == 0) continue;
        const Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 6, 6> z = basis.transpose() * block;
        reduced.middleRows(directions.first[static_cast<std::size_t>(at.first)], basis.cols())
            .noalias() -= z.lazyProduct(flexibility.middleRows<6>(6 * at.second));
      }
      rightmost = rightmost_of_low_rank(reduced);
    }
  } else {
    // Arnoldi's method on the operator itself, one solve per step (shift-invert at λ = 0: the
    // solves with K are F).
    MatX load_stiffness = MatX::Zero(n, n);
    for (const auto& [at, block] : placed)
      load_stiffness.block<6, 6>(6 * at.first, 6 * at.second) += block;
    rightmost = rightmost_by_arnoldi(
        [&](const VecX& v) -> VecX {
          const VecX wrench = -(load_stiffness * v);
          EndWrenches& external = solves.external(1);
          for (Index k = 0; k < nodes; ++k)
            external.add(node_ends[static_cast<std::size_t>(k)], 0,
                         weight.asDiagonal() * wrench.segment<6>(6 * k));
          const std::optional<MatX> x = solves.solve();
          if (!x) {
            singular = true;
            return VecX::Zero(n);
          }
          VecX d(n);
          for (Index k = 0; k < nodes; ++k)
            d.segment<6>(6 * k) =
                weight.asDiagonal() *
                x->col(0).segment<6>(deflection_column(node_ends[static_cast<std::size_t>(k)]));
          return d;
        },
        n);
    if (!singular && rightmost && !rightmost->converged)
      notes.push_back(
          "the critical load factor's iteration did not converge; the factor given is its last "
          "estimate");
  }
  if (singular) {
    notes.push_back(
        "the critical load factor is not found: the unloaded structure's system is singular "
        "(a mechanism, or a structure held rigidly more than once)");
    return {};
  }
  if (!rightmost) return {};
  CriticalLoad critical;
  critical.factor = 1 / rightmost->value;
  // The whole mode: the deflections under the load terms' wrenches −K_L·Δt_S at the nodes. On
  // the dense way these are the combination of U's columns the eigenvector gives
  // (−Z·F·U·y = μ·y), whose solutions are at hand.
  VecX mode;
  if (unknowns_per_direction.size() > 0) {
    mode = unknowns_per_direction * rightmost->vector;
  } else {
    MatX load_stiffness = MatX::Zero(n, n);
    for (const auto& [at, block] : placed)
      load_stiffness.block<6, 6>(6 * at.first, 6 * at.second) += block;
    const VecX wrench = -(load_stiffness * rightmost->vector);
    EndWrenches& external = solves.external(1);
    for (Index k = 0; k < nodes; ++k)
      external.add(node_ends[static_cast<std::size_t>(k)], 0,
                   weight.asDiagonal() * wrench.segment<6>(6 * k));
    std::optional<MatX> x = solves.solve();
    if (!x) return {};
    mode = x->col(0);
  }
  critical.mode = describe_mode(model, topology, blocks, mode);
  if (solves.residual() > options.max_relative_residual)
    notes.push_back("the critical load factor's solves leave a relative residual of " +
                    std::to_string(solves.residual()) + "; it may be inaccurate");
  return critical;
}

void add_critical_loads(const Model& model, const Topology& topology,
                        const std::vector<SpinLock>& locks, const SolveOptions& options,
                        const std::vector<CaseLoads>& cases, Result& result,
                        const CriticalLoadReuse& reuse) {
  // The cases in the order case_loads gives them: the unnamed one where there is one, then
  // the named ones, as Result holds them (the self-weight column after them is no case).
  const bool unnamed = has_unnamed_case(model);
  const std::size_t first_named = unnamed ? 1 : 0;
  for (std::size_t c = 0; c < result.load_cases.size(); ++c) {
    Result& case_result = result.load_cases[c];
    case_result.critical_load = critical_load(
        model, topology, locks, options, case_result, cases[first_named + c].applied_at_ends(),
        case_result.report.notes, EigenMethod::automatic, reuse);
  }
  if (!unnamed && !result.load_cases.empty()) {
    result.critical_load = result.load_cases.front().critical_load;
    return;
  }
  result.critical_load =
      critical_load(model, topology, locks, options, result, cases.front().applied_at_ends(),
                    result.report.notes, EigenMethod::automatic, reuse);
}

}  // namespace stiffmsa::detail
