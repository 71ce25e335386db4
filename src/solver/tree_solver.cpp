#include "solver/tree_solver.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include <Eigen/LU>

#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

std::optional<TreeOrder> tree_order(const Topology& topology) {
  const auto group_count = static_cast<int>(topology.groups.size());
  TreeOrder order;
  // Other supports close loops through the ground: they are cut (tree_passes.hpp).
  for (int g = 0; g < group_count && order.root < 0; ++g)
    if (topology.groups[static_cast<std::size_t>(g)].kind == ConnectionGroup::Kind::support)
      order.root = g;
  if (order.root < 0 || group_count != topology.link_count + 1) return std::nullopt;
  std::vector<char> reached(static_cast<std::size_t>(group_count), 0);
  order.groups.reserve(static_cast<std::size_t>(group_count));
  order.toward_root.reserve(static_cast<std::size_t>(group_count));
  order.groups.push_back(order.root);
  order.toward_root.push_back(-1);
  reached[static_cast<std::size_t>(order.root)] = 1;
  std::vector<int> depth{0};  // per entry of the order: links from the root
  depth.reserve(static_cast<std::size_t>(group_count));
  for (std::size_t next = 0; next < order.groups.size(); ++next) {
    const ConnectionGroup& group = topology.groups[static_cast<std::size_t>(order.groups[next])];
    for (int end : group.ends) {
      if (end == order.toward_root[next]) continue;
      const int far_end = end ^ 1;  // the other end of the same link
      const int far_group = topology.group_of_end[static_cast<std::size_t>(far_end)];
      if (reached[static_cast<std::size_t>(far_group)]) return std::nullopt;  // a loop
      reached[static_cast<std::size_t>(far_group)] = 1;
      order.groups.push_back(far_group);
      order.toward_root.push_back(far_end);
      depth.push_back(depth[next] + 1);
      order.depth = std::max(order.depth, depth.back());
    }
  }
  if (order.groups.size() != static_cast<std::size_t>(group_count))
    return std::nullopt;  // not connected
  return order;
}

bool passes_tree(const Blocks& blocks) {
  return std::all_of(blocks.begin(), blocks.end(),
                     [](const auto& block) { return passes_tree(*block); });
}

EndWrenches load_cases(const Model& model, const Topology& topology) {
  EndWrenches cases;
  load_cases_into(model, topology, cases);
  return cases;
}

void load_cases_into(const Model& model, const Topology& topology, EndWrenches& cases) {
  cases.reset(topology.end_count(), 1 + 6 * static_cast<Index>(topology.effector_ends.size()));
  for (std::size_t i = 0; i < model.loads.size(); ++i)
    if (!model.loads[i].wrench.isZero(0))
      cases.add(topology.load_ends[i], kLoadCase, model.loads[i].wrench);
  for (std::size_t e = 0; e < topology.effector_ends.size(); ++e)
    for (int c = 0; c < 6; ++c)
      cases.add(topology.effector_ends[e], 1 + 6 * static_cast<Index>(e) + c, Vec6::Unit(c));
}

namespace {

// The number of load cases, known at compile time where the check is instantiated for it:
// the loops over a row's k adjacent values are then unrolled and vectorised.
template <int Columns>
Index width(Index runtime) {
  return Columns == Eigen::Dynamic ? runtime : Columns;
}

// The largest |entry| of each column over the rows added so far, and whether every entry was
// finite (a maximum alone would drop a NaN coefficient, residual or unknown, and the check pass
// them): v·0 is 0 for a finite v and NaN for an infinite or NaN one, so a sum of them marks a
// value that is not without a branch, and the loops vectorise. One mark serves all columns: a
// column that is not finite makes the check's largest residual infinite whichever it is. Where
// k is known, rows are taken two at a time, as one run of 2k values (whole vector registers even
// for an odd k), into accumulators that are reduced only when a maximum is read: the check adds
// a few rows of every block, and a reduction per call cost more than the rows. The loops run on
// local copies of them, which stay in registers (members would be stored and loaded again at
// every row, as far as the compiler knows `values` could point into them).
template <int Columns>
class ColumnMaxima {
 public:
  explicit ColumnMaxima(Index columns) : largest_(Values::Zero(columns)) {}
  // `rows` rows of the columns, stored by rows one after the other.
  void add(const double* values, Index rows) {
    if constexpr (Columns != Eigen::Dynamic) {
      Pair largest = pair_largest_;
      Lane marks = marks_;
      Index i = 0;
      for (; i + 1 < rows; i += 2, values += 2 * Columns) {
        largest = largest.max(Eigen::Map<const Pair>(values).abs());
        for (int lane = 0; lane < Columns; ++lane)
          marks += Eigen::Map<const Lane>(values + 2 * lane) * 0.0;
      }
      pair_largest_ = largest;
      if (i < rows) {
        const Eigen::Map<const Values> last_row(values);
        largest_ = largest_.max(last_row.abs());
        marks(0) += (last_row * 0.0).sum();
      }
      marks_ = marks;
    } else {
      const Index columns = largest_.size();
      double marks = 0;
      for (Index i = 0; i < rows; ++i, values += columns)
        for (Index c = 0; c < columns; ++c) {
          largest_(c) = std::max(largest_(c), std::abs(values[c]));
          marks += values[c] * 0.0;
        }
      marks_(0) += marks;
    }
  }
  bool finite() const { return marks_.sum() == 0; }
  double operator()(Index column) const {
    double largest = largest_(column);
    if constexpr (Columns != Eigen::Dynamic)
      largest = std::max({largest, pair_largest_(column), pair_largest_(Columns + column)});
    return largest;
  }

 private:
  using Values = Eigen::Array<double, Columns, 1>;  // on the stack where k is known
  using Pair = Eigen::Array<double, Columns == Eigen::Dynamic ? 1 : 2 * Columns, 1>;
  using Lane = Eigen::Array2d;  // one vector register
  Values largest_;
  Pair pair_largest_ = Pair::Zero();
  Lane marks_ = Lane::Zero();
};

// FNV-1a over the written positions, a block of them at a time: (row, column, rows, columns)
// for a dense block, (row, column, size, −1) for a scaled identity. Both writers of the tree
// solve hash through it, so that a pose's blocks and the reference's give the same fingerprint
// exactly when they write the same positions.
class PositionHash {
 public:
  void block(Index row, Index column, const CoefficientBlock& coefficients) {
    record({row, column, coefficients.rows(), coefficients.cols()});
  }
  void identity(Index row, Index column, Index size) { record({row, column, size, -1}); }
  std::uint64_t hash = 0xcbf29ce484222325ULL;

 private:
  void record(std::initializer_list<Index> values) {
    for (const Index value : values) {
      hash ^= static_cast<std::uint64_t>(value);
      hash *= 0x100000001b3ULL;
    }
  }
};

class PatternHash final : public EquationWriter, public PositionHash {
 public:
  void add_coefficients(Index row, Index column, const CoefficientBlock& coefficients,
                        double) override {
    block(row, column, coefficients);
  }
  void add_identity(Index row, Index column, Index size, double) override {
    identity(row, column, size);
  }
};

// r = −A_block·x over one block's rows (written from row 0), the row sums of |A_block|, and
// the count of its nonzero coefficients. The residual and x are stored by rows, so that a row
// of a written block updates its k adjacent sums, kept in registers while the row's
// coefficients go by, and a scaled identity is one loop over adjacent values. The buffers, the
// caller's, have the largest block's rows: a workspace's scratch keeps them from pose to pose.
template <int Columns>
class BlockResidual final : public EquationWriter, public PositionHash {
 public:
  // `residual` and `row_sums` are the caller's buffers, resized to the largest block's rows.
  BlockResidual(const RowMajorMatX& x, Index most_rows, RowMajorMatX& residual, VecX& row_sums)
      : x_(x), residual_(residual), row_sums_(row_sums) {
    residual_.resize(most_rows, x.cols());
    row_sums_.resize(most_rows);
  }
  void start(Index rows) {
    rows_ = rows;
    residual_.topRows(rows).setZero();
    row_sums_.head(rows).setZero();
  }
  auto residual() { return residual_.topRows(rows_); }
  auto row_sums() const { return row_sums_.head(rows_); }

  void add_coefficients(Index row, Index column, const CoefficientBlock& coefficients,
                        double scale) override {
    block(row, column, coefficients);
    const Index rows = coefficients.rows(), columns = coefficients.cols();
    eigen_assert(row >= 0 && row + rows <= rows_ && column >= 0 && column + columns <= x_.rows());
    const Index k = width<Columns>(x_.cols());
    const double* const in = x_.data() + column * k;
    long block_nonzeros = 0;
    for (Index i = 0; i < rows; ++i) {
      double* const out = residual_.data() + (row + i) * k;
      double magnitude = 0;
      if constexpr (Columns != Eigen::Dynamic) {
        using Row = Eigen::Array<double, 1, Columns>;
        Row sums = Row::Zero();
        for (Index j = 0; j < columns; ++j) {
          const double value = scale * coefficients(i, j);
          // Most of a joint's Λ_r and of a link's [d×] are zeros: a row of k products saved each.
          if (value == 0) continue;
          ++block_nonzeros;
          magnitude += std::abs(value);
          sums += value * Eigen::Map<const Row>(in + j * Columns);
        }
        Eigen::Map<Row>(out) -= sums;
      } else {
        for (Index j = 0; j < columns; ++j) {
          const double value = scale * coefficients(i, j);
          block_nonzeros += value != 0;
          magnitude += std::abs(value);
          for (Index c = 0; c < k; ++c) out[c] -= value * in[j * k + c];
        }
      }
      row_sums_(row + i) += magnitude;
    }
    nonzeros += block_nonzeros;
  }
  void add_identity(Index row, Index column, Index size, double scale) override {
    identity(row, column, size);
    eigen_assert(row >= 0 && row + size <= rows_ && column >= 0 && column + size <= x_.rows());
    if (scale == 0) return;
    nonzeros += size;
    row_sums_.segment(row, size).array() += std::abs(scale);
    // The residual and x are separate buffers: one run of size·k values, as arrays that do not
    // alias.
    const Index k = width<Columns>(x_.cols());
    Eigen::Map<Eigen::ArrayXd> out(residual_.data() + row * k, size * k);
    const Eigen::Map<const Eigen::ArrayXd> in(x_.data() + column * k, size * k);
    if (scale == 1)  // most identities: a link's and a joint's W and Δt, without a product each
      out -= in;
    else if (scale == -1)
      out += in;
    else
      out -= scale * in;
  }
  long nonzeros = 0;

 private:
  const RowMajorMatX& x_;
  RowMajorMatX& residual_;
  VecX& row_sums_;
  Index rows_ = 0;
};

// The rows of the largest block: the size of the buffers that hold one block's rows at a time.
Index most_equation_rows(const Blocks& blocks) {
  Index most = 0;
  for (const auto& block : blocks) most = std::max(most, block->equation_count());
  return most;
}

// The right-hand side of block `k` (its rows × the load cases, from row 0 of `rhs`): the loads
// at the link ends it holds (links hold none; connection group g is block link_count + g) and
// its preload. False, with `rhs` untouched, where it is zero. `column` is scratch of the
// block's rows at least.
bool block_rhs(const Blocks& blocks, std::size_t k, const Topology& topology,
               const EndWrenches& external, VecX& column, RowMajorMatX& rhs) {
  const ElementBlock& block = *blocks[k];
  const Index rows = block.equation_count();
  auto block_column = column.head(rows);
  auto block_rhs = rhs.topRows(rows);
  bool any_rhs = false;
  if (block.has_preload()) {
    block_column.setZero();
    block.add_preload(0, column);
    any_rhs = !block_column.isZero(0);
    if (any_rhs) {
      block_rhs.setZero();
      for (Index c = 0; c < external.state_columns(); ++c) block_rhs.col(c) = block_column;
    }
  }
  if (k >= static_cast<std::size_t>(topology.link_count))
    for (int end : topology.groups[k - static_cast<std::size_t>(topology.link_count)].ends) {
      if (!external.any_at(end)) continue;
      if (!any_rhs) block_rhs.setZero();
      any_rhs = true;
      for (Index c = 0; c < external.columns(); ++c) {
        block_column.setZero();
        block.add_external_wrench(0, end, external.at(end).col(c), column);
        block_rhs.col(c) += block_column;
      }
    }
  return any_rhs;
}

// A block's right-hand side, in buffers of the largest block's rows: a block writes only its
// own rows, from row 0.
void size_rhs_buffers(VecX& column, RowMajorMatX& rhs, Index most_rows, Index columns) {
  column.resize(most_rows);
  rhs.resize(most_rows, columns);
}

template <int Columns>
BlockCheck check_blocks(const Blocks& blocks, const Topology& topology, const RowMajorMatX& x,
                        const EndWrenches& external, TreeScratch& scratch) {
  const Index columns = x.cols();
  const Index most_rows = most_equation_rows(blocks);
  BlockResidual<Columns> block_residual(x, most_rows, scratch.block_residual, scratch.row_sums);
  VecX& column = scratch.column;
  RowMajorMatX& rhs = scratch.block_rhs;
  size_rhs_buffers(column, rhs, most_rows, columns);
  ColumnMaxima<1> a_norm(1);
  ColumnMaxima<Columns> residual_norm(columns), rhs_norm(columns), x_norm(columns);
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const ElementBlock& block = *blocks[k];
    const Index rows = block.equation_count();
    block_residual.start(rows);
    block.write_equations(0, block_residual);
    a_norm.add(block_residual.row_sums().data(), rows);
    auto residual = block_residual.residual();
    if (block_rhs(blocks, k, topology, external, column, rhs)) {
      residual += rhs.topRows(rows);
      rhs_norm.add(rhs.data(), rows);
    }
    residual_norm.add(residual.data(), rows);
  }
  BlockCheck check;
  check.nonzeros = block_residual.nonzeros;
  check.pattern = block_residual.hash;
  x_norm.add(x.data(), x.rows());
  if (!(a_norm.finite() && x_norm.finite() && rhs_norm.finite() && residual_norm.finite())) {
    check.relative_residual = INFINITY;
    return check;
  }
  for (Index c = 0; c < columns; ++c) {
    const double error =
        normwise_backward_error(residual_norm(c), a_norm(0), x_norm(c), rhs_norm(c));
    if (!(error <= check.relative_residual)) check.relative_residual = error;
  }
  return check;
}

}  // namespace

std::uint64_t pattern_fingerprint(const Blocks& blocks) {
  PatternHash hash;
  for (const auto& block : blocks) block->write_equations(0, hash);
  return hash.hash;
}

BlockCheck check_block_by_block(const Blocks& blocks, const Topology& topology,
                                const RowMajorMatX& x, const EndWrenches& external,
                                TreeScratch& scratch) {
  // One end effector, 1 + 6 load cases, is the common case.
  if (x.cols() == 7) return check_blocks<7>(blocks, topology, x, external, scratch);
  return check_blocks<Eigen::Dynamic>(blocks, topology, x, external, scratch);
}

namespace {
// Above 1 MiB a buffer is not kept: a robot's are a few kilobytes, a 100 000-link chain's 134 MB.
void release_if_large(RowMajorMatX& buffer) {
  if (buffer.size() > (Index{1} << 17)) buffer.resize(0, 0);
}
}  // namespace

void TreeScratch::release_large() {
  for (RowMajorMatX* buffer :
       {&x, &x_low, &first_run, &first_run_low, &cut_rhs, &block_residual, &block_rhs})
    release_if_large(*buffer);
}

namespace {

// Where each cut block's unknowns start, per entry of the order (blocks not cut have none).
struct CutLayout {
  std::vector<Index>& first;  // a scratch buffer
  Index unknowns = 0;
};

CutLayout cut_layout(const Blocks& blocks, int link_count, const TreeOrder& order,
                     std::vector<Index>& first) {
  CutLayout layout{first};
  layout.first.clear();
  for (std::size_t k = 0; k < order.groups.size(); ++k) {
    layout.first.push_back(layout.unknowns);
    layout.unknowns += cut_unknowns(*blocks[static_cast<std::size_t>(link_count + order.groups[k])],
                                    order.toward_root[k]);
  }
  return layout;
}

// The passes, a long model's low parts released after them, so that they do not add to the
// peak beyond the passes.
void passes(const Blocks& blocks, int link_count, const TreeOrder& order, const CutLayout& layout,
            const RowMajorMatX* cut_values, const EndWrenches& external, Index unknowns,
            bool compensated, RowMajorMatX& x, RowMajorMatX& x_low, RowMajorMatX& increment) {
  run_passes(blocks, link_count, order, layout.first, cut_values, external, unknowns, compensated,
             x, x_low, increment);
  if (compensated) release_if_large(x_low);
}

// −A·x on chosen rows of a block, each added into a row of `out`: the cut rows alone, so that
// the other rows' coefficients cost a comparison each.
class CutRowResidual final : public CoefficientWriter<CutRowResidual> {
 public:
  // `target` is scratch.
  CutRowResidual(const RowMajorMatX& x, RowMajorMatX& out, Index most_rows,
                 std::vector<Index>& target)
      : x_(x), out_(out), target_(target) {
    target_.resize(static_cast<std::size_t>(most_rows));
  }
  // The block's cut rows go to rows first_out, first_out + 1, … of `out`; its other rows nowhere.
  void start(const std::vector<Index>& rows, Index first_out) {
    std::fill(target_.begin(), target_.end(), -1);
    for (std::size_t i = 0; i < rows.size(); ++i)
      target_[static_cast<std::size_t>(rows[i])] = first_out + static_cast<Index>(i);
  }
  void put(Index row, Index column, double value) {
    const Index target = target_[static_cast<std::size_t>(row)];
    if (target < 0 || value == 0) return;
    const Index columns = x_.cols();
    // Separate buffers: saying so lets the loop run two columns at a time.
    double* __restrict const out = out_.data() + target * columns;
    const double* __restrict const in = x_.data() + column * columns;
    for (Index c = 0; c < columns; ++c) out[c] -= value * in[c];
  }

 private:
  const RowMajorMatX& x_;
  RowMajorMatX& out_;
  std::vector<Index>& target_;
};

// b − A·x on the cut rows of the cut blocks, in the order of the layout (m rows), into
// scratch.cut_residuals.
void cut_residuals(const Blocks& blocks, const Topology& topology, const TreeOrder& order,
                   const RowMajorMatX& x, const EndWrenches& external, Index m,
                   TreeScratch& scratch) {
  const Index most_rows = most_equation_rows(blocks);
  RowMajorMatX& values = scratch.cut_residuals;
  values.setZero(m, x.cols());
  CutRowResidual residual(x, values, most_rows, scratch.cut_targets);
  VecX& column = scratch.column;
  RowMajorMatX& rhs = scratch.cut_rhs;
  size_rhs_buffers(column, rhs, most_rows, x.cols());
  std::vector<Index>& rows = scratch.cut_rows;
  Index next = 0;
  for (std::size_t k = 0; k < order.groups.size(); ++k) {
    const std::size_t b = static_cast<std::size_t>(topology.link_count + order.groups[k]);
    const ElementBlock& block = *blocks[b];
    rows.clear();
    add_cut_rows(block, order.toward_root[k], rows);
    if (rows.empty()) continue;
    residual.start(rows, next);
    block.write_equations(0, residual);
    if (block_rhs(blocks, b, topology, external, column, rhs))
      for (std::size_t i = 0; i < rows.size(); ++i)
        values.row(next + static_cast<Index>(i)) += rhs.row(rows[i]);
    next += static_cast<Index>(rows.size());
  }
  eigen_assert(next == m);
}

}  // namespace

double rcond_lower_bound(const MatX& a, const Eigen::PartialPivLU<MatX>& lu, VecX& scratch) {
  const MatX& packed = lu.matrixLU();  // U on and above the diagonal, L (unit diagonal) below
  const Index n = packed.rows();
  if (n == 0) return 0;
  const double l1_norm = a.cwiseAbs().colwise().sum().maxCoeff();  // as the estimate takes it
  scratch.resize(n);
  double* const w = scratch.data();
  const double* const columns = packed.data();
  // M(U)ᵀ·y = e, forward: |u_jj|·y_j = 1 + Σ_{i<j} |u_ij|·y_i.
  for (Index j = 0; j < n; ++j) {
    const double* const column = columns + j * n;
    double sum = 1;
    for (Index i = 0; i < j; ++i) sum += std::abs(column[i]) * w[i];
    w[j] = sum / std::abs(column[j]);
  }
  // M(L)ᵀ·w = y, backward: w_j = y_j + Σ_{i>j} |l_ij|·w_i.
  for (Index j = n - 1; j-- > 0;) {
    const double* const column = columns + j * n;
    double sum = 0;
    for (Index i = j + 1; i < n; ++i) sum += std::abs(column[i]) * w[i];
    w[j] += sum;
  }
  double largest = 0;
  for (Index j = 0; j < n; ++j) {
    if (!(w[j] < INFINITY)) return 0;  // a zero pivot, or a value that is not finite
    largest = std::max(largest, w[j]);
  }
  const double bound = 1 / (l1_norm * largest);
  return std::isfinite(bound) ? bound : 0;
}

std::optional<Index> tree_solve(const Blocks& blocks, const Topology& topology,
                                const TreeOrder& order, const EndWrenches& external,
                                double least_rcond, TreeScratch& scratch, Index most_cut_unknowns,
                                int compensated_from_depth) {
  const bool compensated = order.depth >= compensated_from_depth;
  const int link_count = topology.link_count;
  const Index unknowns = topology.unknowns();
  const CutLayout layout = cut_layout(blocks, link_count, order, scratch.cut_first);
  const Index m = layout.unknowns;
  if (m == 0) {
    passes(blocks, link_count, order, layout, nullptr, external, unknowns, compensated, scratch.x,
           scratch.x_low, scratch.increment);
    return 0;
  }
  if (m > most_cut_unknowns) return std::nullopt;

  // First run: the load cases with the cut unknowns at zero, then each cut unknown at 1 alone.
  const Index k = external.columns();
  EndWrenches& widened = scratch.widened;
  external.widen_into(k + m, widened);
  RowMajorMatX& unit_values = scratch.unit_values;
  // Only this writes it, always the same for a size: the poses of a workspace keep it.
  if (unit_values.rows() != m || unit_values.cols() != k + m) {
    unit_values.setZero(m, k + m);
    unit_values.rightCols(m).setIdentity();
  }
  RowMajorMatX& x = scratch.first_run;
  passes(blocks, link_count, order, layout, &unit_values, widened, unknowns, compensated, x,
         scratch.first_run_low, scratch.increment);

  // The cut rows' residuals b − A·x: affine in the cut unknowns z, T_load + T_cut·z.
  cut_residuals(blocks, topology, order, x, widened, m, scratch);
  const RowMajorMatX& t = scratch.cut_residuals;
  release_if_large(x);  // a long model's first run is not needed beside the second

  // T_cut·z = −T_load, equilibrated (rows, then columns, to a largest entry of 1) so that the
  // condition estimate does not depend on units: reactions in N beside motions in rad.
  if (!t.allFinite()) return std::nullopt;
  MatX& a = scratch.cut_matrix;
  a = t.rightCols(m);
  VecX& row_scale = scratch.row_scale;
  VecX& column_scale = scratch.column_scale;
  row_scale.resize(m);
  column_scale.resize(m);
  for (Index i = 0; i < m; ++i) {
    // T's rows are adjacent in memory, a's are not: the same values, read in one run.
    const double largest = t.row(i).tail(m).cwiseAbs().maxCoeff();
    if (!(largest > 0)) return std::nullopt;
    row_scale(i) = 1 / largest;
  }
  for (Index j = 0; j < m; ++j) {
    auto column = a.col(j);
    column.array() *= row_scale.array();
    const double largest = column.cwiseAbs().maxCoeff();
    if (!(largest > 0)) return std::nullopt;
    column_scale(j) = 1 / largest;
    column *= column_scale(j);
  }
  const Eigen::PartialPivLU<MatX>& lu = scratch.cut_lu.compute(a);
  // The estimate decides, but where the bound below it clears the threshold by far it cannot
  // decide otherwise, and costs less than the LU (bench/README.md, "Session 5: sweep poses").
  const double least_bound = least_rcond / kConditionBoundMargin;
  if (!(rcond_lower_bound(a, lu, scratch.condition_bound) >= least_bound) &&
      !(lu.rcond() >= least_rcond))
    return std::nullopt;
  MatX& rhs = scratch.cut_load;
  rhs = t.leftCols(k);
  for (Index c = 0; c < k; ++c) rhs.col(c).array() *= -row_scale.array();
  MatX& z = scratch.cut_solution;
  z = lu.solve(rhs);
  for (Index c = 0; c < k; ++c) z.col(c).array() *= column_scale.array();
  if (!z.allFinite()) return std::nullopt;

  // Second run: the load cases with the cut unknowns solved.
  RowMajorMatX& cut_values = scratch.cut_values;
  cut_values = z;
  passes(blocks, link_count, order, layout, &cut_values, external, unknowns, compensated, scratch.x,
         scratch.x_low, scratch.increment);
  return m;
}

std::optional<Index> tree_solve_with_cut_system_of(const TreeScratch& solved, const Blocks& blocks,
                                                   const Topology& topology, const TreeOrder& order,
                                                   const EndWrenches& external,
                                                   TreeScratch& scratch) {
  const bool compensated = order.depth >= kCompensatedFromDepth;
  const int link_count = topology.link_count;
  const Index unknowns = topology.unknowns();
  const CutLayout layout = cut_layout(blocks, link_count, order, scratch.cut_first);
  const Index m = layout.unknowns;
  if (m == 0 || solved.cut_lu.rows() != m || solved.row_scale.size() != m ||
      solved.column_scale.size() != m)
    return std::nullopt;

  // First run: the columns with the cut unknowns at zero; the cut rows' residuals are T_load.
  const Index k = external.columns();
  RowMajorMatX& zero_values = scratch.zero_values;
  zero_values.setZero(m, k);
  RowMajorMatX& x = scratch.first_run;
  passes(blocks, link_count, order, layout, &zero_values, external, unknowns, compensated, x,
         scratch.first_run_low, scratch.increment);
  cut_residuals(blocks, topology, order, x, external, m, scratch);
  release_if_large(x);
  const RowMajorMatX& t = scratch.cut_residuals;
  if (!t.allFinite()) return std::nullopt;
  MatX& rhs = scratch.cut_load;
  rhs = t;
  for (Index c = 0; c < k; ++c) rhs.col(c).array() *= -solved.row_scale.array();
  MatX& z = scratch.cut_solution;
  z = solved.cut_lu.solve(rhs);
  for (Index c = 0; c < k; ++c) z.col(c).array() *= solved.column_scale.array();
  if (!z.allFinite()) return std::nullopt;

  // Second run: the columns with the cut unknowns solved.
  RowMajorMatX& cut_values = scratch.cut_values;
  cut_values = z;
  passes(blocks, link_count, order, layout, &cut_values, external, unknowns, compensated, scratch.x,
         scratch.x_low, scratch.increment);
  return m;
}

}  // namespace stiffmsa::detail
