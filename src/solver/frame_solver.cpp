#include "solver/frame_solver.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "stiffmsa/config.hpp"
#if STIFFMSA_HAVE_SUITESPARSE
#include <Eigen/CholmodSupport>
#endif
#if STIFFMSA_HAVE_OPENMP_RUNTIME
#include <omp.h>
#endif

#include "elements/cad_link.hpp"
#include "elements/element_kinds.hpp"
#include "solver/blas_lock.hpp"
#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

namespace {
// Whether a connection block welds its link ends: no free direction (a locked actuator is held
// so); a free end, which has no directions, holds one end alone.
bool welds(const ElementBlock& connection) {
  const FreeDirections* directions = connection.directions();
  return !directions || directions->p == 0;
}
}  // namespace

std::optional<Mat12> end_stiffness(const ElementBlock& link) {
  switch (link.kind()) {
    case BlockKind::link: {
      const auto& flexible = static_cast<const LinkBlock&>(link);
      if (!flexible.compliance()) return std::nullopt;
      return free_free_stiffness(*flexible.compliance(), flexible.d());
    }
    case BlockKind::stiffness_link: return static_cast<const StiffnessLinkBlock&>(link).stiffness();
    default: return std::nullopt;
  }
}

namespace {
// Whether end_stiffness(link) has one, without forming it: a frame's plan asks every link.
bool has_end_stiffness(const ElementBlock& link) {
  switch (link.kind()) {
    case BlockKind::link: return static_cast<const LinkBlock&>(link).compliance().has_value();
    case BlockKind::stiffness_link: return true;
    default: return false;
  }
}
}  // namespace

std::optional<FramePlan> frame_plan(const Topology& topology, const Blocks& blocks) {
  FramePlan plan;
  plan.node_of_end.assign(static_cast<std::size_t>(topology.end_count()), -1);
  bool supported = false;
  for (std::size_t g = 0; g < topology.groups.size(); ++g) {
    const ConnectionGroup& group = topology.groups[g];
    if (!welds(*blocks[static_cast<std::size_t>(topology.link_count) + g])) return std::nullopt;
    if (group.kind == ConnectionGroup::Kind::support) {
      supported = true;
      continue;  // its ends stay at −1: held in place
    }
    for (int end : group.ends) plan.node_of_end[static_cast<std::size_t>(end)] = plan.nodes;
    ++plan.nodes;
  }
  if (!supported || plan.nodes == 0) return std::nullopt;
  for (int l = 0; l < topology.link_count; ++l)
    if (!has_end_stiffness(*blocks[static_cast<std::size_t>(l)])) return std::nullopt;

  // K's pattern: the nodes in each node's block column, sorted.
  auto node_of = [&](int l, int a) {
    return plan.node_of_end[static_cast<std::size_t>(2 * l + a)];
  };
  std::vector<std::vector<int>> rows_of(static_cast<std::size_t>(plan.nodes));
  for (int l = 0; l < topology.link_count; ++l)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        if (node_of(l, a) >= 0 && node_of(l, b) >= 0)
          rows_of[static_cast<std::size_t>(node_of(l, b))].push_back(node_of(l, a));
  for (std::vector<int>& rows : rows_of) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  plan.column_starts.reserve(6 * static_cast<std::size_t>(plan.nodes) + 1);
  plan.column_starts.push_back(0);
  std::vector<int> first_of_node(static_cast<std::size_t>(plan.nodes));
  for (int node = 0; node < plan.nodes; ++node) {
    const std::vector<int>& rows = rows_of[static_cast<std::size_t>(node)];
    first_of_node[static_cast<std::size_t>(node)] = plan.column_starts.back();
    for (int j = 0; j < 6; ++j) {
      for (int row : rows)
        for (int i = 0; i < 6; ++i) plan.rows.push_back(6 * row + i);
      plan.column_starts.push_back(static_cast<int>(plan.rows.size()));
    }
  }
  plan.parts.resize(4 * static_cast<std::size_t>(topology.link_count));
  for (int l = 0; l < topology.link_count; ++l)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const int row_node = node_of(l, a), column_node = node_of(l, b);
        if (row_node < 0 || column_node < 0) continue;
        const std::vector<int>& rows = rows_of[static_cast<std::size_t>(column_node)];
        const auto at = std::lower_bound(rows.begin(), rows.end(), row_node) - rows.begin();
        FramePlan::Part& part = plan.parts[static_cast<std::size_t>(4 * l + 2 * a + b)];
        part.first =
            first_of_node[static_cast<std::size_t>(column_node)] + 6 * static_cast<int>(at);
        part.stride = 6 * static_cast<int>(rows.size());
      }
  return plan;
}

namespace {

// CHOLMOD's supernodal factorisation zeroes and fills each large supernode in an OpenMP team of
// a fixed 4 threads (its CHOLMOD_OMP_NUM_THREADS), whatever the cores and OMP_NUM_THREADS: on
// 2 cores, or in a sweep whose workers each solve, the threads outnumber the cores and wait on
// one another (the 960-beam frame's command on 2 cores 46 → 33 ms without them, bench/README.md
// round 9). While this lives, OpenMP regions started by the calling thread are inactive and run
// on it. max-active-levels must be an ICV of the calling thread's task, as in libgomp from
// GCC 11 (CMakeLists.txt), so that other threads of the program keep theirs. With a BLAS built
// on OpenMP (not the serial OpenBLAS that scripts/install-deps.sh installs), its threads inside
// CHOLMOD would be held to the calling thread too.
#if STIFFMSA_HAVE_OPENMP_RUNTIME
class OpenMPOnCallingThread {
 public:
  OpenMPOnCallingThread() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~OpenMPOnCallingThread() { omp_set_max_active_levels(levels_); }
  OpenMPOnCallingThread(const OpenMPOnCallingThread&) = delete;
  OpenMPOnCallingThread& operator=(const OpenMPOnCallingThread&) = delete;

 private:
  int levels_;
};
#else
struct OpenMPOnCallingThread {};
#endif

// The Cholesky factorisation of the (scaled) stiffness, as a LinearSolver for the condition
// estimate. CHOLMOD's supernodal one where SuiteSparse is built in: a frame's factor has dense
// column blocks, which it factorises through BLAS (with OpenBLAS ~2× the simplicial one on the
// 960-beam frame).
class StiffnessCholesky final : public LinearSolver {
 public:
#if STIFFMSA_HAVE_SUITESPARSE
  // The library prints nothing: CHOLMOD would report a matrix that is not positive definite
  // (a part held by no support) on stdout; the solve's result says it instead.
  StiffnessCholesky() { cholesky_.cholmod().print = 0; }
#endif
  void analyze(const SparseMatrix& k) override { cholesky_.analyzePattern(k); }
  bool factorize(const SparseMatrix& k) override {
    [[maybe_unused]] const OpenMPOnCallingThread one_thread{};
    const std::lock_guard blas(blas_mutex());
    cholesky_.factorize(k);
    // Positive definite: the factorisation succeeds (a mechanism or a bad stiffness fails it).
    return cholesky_.info() == Eigen::Success && positive_pivots();
  }
  void solve(MatX& b) const override {
    const std::lock_guard blas(blas_mutex());
    b = cholesky_.solve(b);
  }
  void solve_transposed(MatX& b) const override { solve(b); }  // symmetric
  const char* name() const override { return "cholesky"; }
  double determinant_sign() const override { return 1; }  // positive definite once factorised

 private:
#if STIFFMSA_HAVE_SUITESPARSE
  bool positive_pivots() const { return true; }  // an LLᵀ that succeeded has them
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> cholesky_;
#else
  bool positive_pivots() const { return (cholesky_.vectorD().array() > 0).all(); }
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> cholesky_;
#endif
};

}  // namespace

std::optional<FrameSolution> frame_solve(const Blocks& blocks, const Topology& topology,
                                         const FramePlan& plan, const EndWrenches& external,
                                         RowMajorMatX& x, double least_rcond) {
  const Index n = 6 * static_cast<Index>(plan.nodes);
  const Index columns = external.columns();
  auto node_of = [&](int end) { return plan.node_of_end[static_cast<std::size_t>(end)]; };

  // A pose whose blocks are no frame's (a link made rigid, a weld made a hinge) is declined;
  // its pattern differs, which the factorising solve's assembler then refuses as a changed
  // topology.
  // A rigid support's settlement d: its ends move by d in every load case (the state columns).
  std::vector<std::optional<Vec6>> settled(static_cast<std::size_t>(topology.end_count()));
  for (std::size_t g = 0; g < topology.groups.size(); ++g) {
    const ElementBlock& connection = *blocks[static_cast<std::size_t>(topology.link_count) + g];
    if (!welds(connection)) return std::nullopt;
    if (const std::optional<Vec6> d = connection.settlement())
      for (int end : topology.groups[g].ends) settled[static_cast<std::size_t>(end)] = d;
  }
  // K = Σ K12 over the links, each of its 6×6 parts where both ends have a node, in the plan's
  // pattern; each entry summed in the order of the links, its first term standing alone as in
  // a sum of triplets (−0 is the start that keeps it: −0 + v is v, a −0 term included).
  const std::size_t nonzeros = plan.rows.size();
  SparseMatrix k(n, n);
  k.resizeNonZeros(static_cast<Index>(nonzeros));
  std::copy(plan.column_starts.begin(), plan.column_starts.end(), k.outerIndexPtr());
  std::copy(plan.rows.begin(), plan.rows.end(), k.innerIndexPtr());
  double* values = k.valuePtr();
  std::fill(values, values + nonzeros, -0.0);
  std::vector<Mat12> link_stiffness;
  link_stiffness.reserve(static_cast<std::size_t>(topology.link_count));
  for (int l = 0; l < topology.link_count; ++l) {
    std::optional<Mat12> stiffness = end_stiffness(*blocks[static_cast<std::size_t>(l)]);
    if (!stiffness) return std::nullopt;
    link_stiffness.push_back(*stiffness);
    const Mat12& k12 = link_stiffness.back();
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const FramePlan::Part& part = plan.parts[static_cast<std::size_t>(4 * l + 2 * a + b)];
        if (part.first < 0) continue;
        for (Index j = 0; j < 6; ++j) {
          double* column = values + part.first + j * part.stride;
          for (Index i = 0; i < 6; ++i) column[i] += k12(6 * a + i, 6 * b + j);
        }
      }
  }

  // Scaled to a unit diagonal: K̂ = S·K·S, S = diag(1/√K_ii), so that forces beside moments
  // and metres beside radians do not set the condition estimate.
  const int* rows = k.innerIndexPtr();
  const int* starts = k.outerIndexPtr();
  VecX scale(n);
  for (Index column = 0; column < n; ++column) {
    const int* end = rows + starts[column + 1];
    const int* diagonal = std::lower_bound(rows + starts[column], end, static_cast<int>(column));
    const double value = diagonal != end && *diagonal == column ? values[diagonal - rows] : 0.0;
    if (!(value > 0) || !std::isfinite(value)) return std::nullopt;
    scale(column) = 1 / std::sqrt(value);
  }
  for (Index column = 0; column < n; ++column)
    for (int e = starts[column]; e < starts[column + 1]; ++e)
      values[e] = values[e] * scale(rows[e]) * scale(column);
  StiffnessCholesky cholesky;
  cholesky.analyze(k);
  if (!cholesky.factorize(k)) return std::nullopt;
  const double rcond = estimate_reciprocal_condition(cholesky, k);
  if (!(rcond >= least_rcond)) return std::nullopt;

  // F: the external wrenches at each node's ends, less what the settled supports' motions d
  // push on them (−K_nd·d, the coupling of §7.3's K to the held ends); u = S·K̂⁻¹·S·F.
  MatX u = MatX::Zero(n, columns);
  for (int end = 0; end < topology.end_count(); ++end)
    if (node_of(end) >= 0 && external.any_at(end))
      u.middleRows<6>(6 * node_of(end)) += external.at(end);
  for (int l = 0; l < topology.link_count; ++l)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const int row_node = node_of(2 * l + a);
        const std::optional<Vec6>& d = settled[static_cast<std::size_t>(2 * l + b)];
        if (row_node < 0 || !d) continue;
        const Vec6 push =
            link_stiffness[static_cast<std::size_t>(l)].block<6, 6>(6 * a, 6 * b) * *d;
        for (Index c = 0; c < external.state_columns(); ++c) u.block<6, 1>(6 * row_node, c) -= push;
      }
  u = scale.asDiagonal() * u;
  cholesky.solve(u);
  u = scale.asDiagonal() * u;
  if (!u.allFinite()) return std::nullopt;

  x.resize(topology.unknowns(), columns);
  for (int end = 0; end < topology.end_count(); ++end) {
    auto deflection = x.middleRows<6>(deflection_column(end));
    if (node_of(end) >= 0) {
      deflection = u.middleRows<6>(6 * node_of(end));
    } else {
      deflection.setZero();
      if (const std::optional<Vec6>& d = settled[static_cast<std::size_t>(end)])
        for (Index c = 0; c < external.state_columns(); ++c) deflection.col(c) = *d;
    }
  }
  for (int l = 0; l < topology.link_count; ++l) {
    const Mat12& k12 = link_stiffness[static_cast<std::size_t>(l)];
    const int i = 2 * l, j = 2 * l + 1;
    for (int a = 0; a < 2; ++a) {
      const int end = a == 0 ? i : j;
      x.middleRows<6>(wrench_column(end)).noalias() =
          k12.block<6, 6>(6 * a, 0) * x.middleRows<6>(deflection_column(i)) +
          k12.block<6, 6>(6 * a, 6) * x.middleRows<6>(deflection_column(j));
    }
  }
  return FrameSolution{rcond};
}

}  // namespace stiffmsa::detail
