// The block LU of the loaded mode's tangent (docs/theory.md §15.10).
#include "solver/block_lu.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace stiffmsa::detail {

double power_of_two_scale(double largest) {
  if (!(largest > 0) || !std::isfinite(largest)) return 1.0;
  // A normal `largest` of biased exponent E lies in [2^(E−1023), 2^(E−1022)): its scale is
  // 2^(1022−E), of biased exponent 2045 − E, read off the bits where that is normal too.
  const auto exponent_bits = static_cast<int>(std::bit_cast<std::uint64_t>(largest) >> 52);
  if (exponent_bits > 0 && exponent_bits < 2045)
    return std::bit_cast<double>(static_cast<std::uint64_t>(2045 - exponent_bits) << 52);
  int exponent = 0;
  std::frexp(largest, &exponent);
  return std::ldexp(1.0, -exponent);
}

namespace {

// +1 or −1: the parity of the permutation k ↦ order[k] of 0 … n−1.
int permutation_parity(const std::vector<int>& order) {
  std::vector<char> seen(order.size(), 0);
  int parity = 1;
  for (std::size_t start = 0; start < order.size(); ++start) {
    if (seen[start]) continue;
    std::size_t length = 0;
    for (std::size_t k = start; !seen[k]; k = static_cast<std::size_t>(order[k])) {
      seen[k] = 1;
      ++length;
    }
    if (length % 2 == 0) parity = -parity;
  }
  return parity;
}

// y[first … last) −= y[first − 1]·x[first … last), where that multiplier is not zero: one
// column of the elimination's update (the multiplier is the pivot row's entry).
inline void subtract_multiple(double* __restrict y, const double* __restrict x, Index first,
                              Index last) {
  const double multiplier = y[first - 1];
  if (multiplier == 0) return;
  for (Index i = first; i < last; ++i) y[i] -= multiplier * x[i];
}

// One column of a front after its row swaps: L⁻¹ on its 12 pivot rows, then the Schur update
// of the rows below, each entry updated by the multipliers in their order (as column by column
// with subtract_multiple). The 12 pivot rows' triangle has compile-time bounds, unrolled; so
// have the rows below where the front's `Rows` are known at compile time (0: `m` at run time).
template <int Rows = 0>
inline void update_column(double* __restrict column, const double* __restrict l, Index m) {
  if constexpr (Rows > 0) m = Rows;
  int nonzero[kBlockColumns];
  int count = 0;
#pragma GCC unroll 12
  for (int k = 0; k < kBlockColumns; ++k) {
    const double multiplier = column[k];
    if (multiplier == 0) continue;
    nonzero[count++] = k;
    const double* const pivot_column = l + m * k;
#pragma GCC unroll 12
    for (int i = k + 1; i < kBlockColumns; ++i) column[i] -= multiplier * pivot_column[i];
  }
  for (int t = 0; t < count; ++t) {
    const double multiplier = column[nonzero[t]];
    const double* const pivot_column = l + m * nonzero[t];
    for (Index i = kBlockColumns; i < m; ++i) column[i] -= multiplier * pivot_column[i];
  }
}

// Gaussian elimination with partial pivoting of a front's first 12 columns (`m` rows, `width`
// columns, column-major), then the other columns one by one: the row swaps, L⁻¹ and the Schur
// update, in the order of a right-looking elimination of the whole front (every entry sees the
// same operations in the same order). `Rows` > 0: m = Rows at compile time, the loops' bounds
// constant (the pivot steps unrolled), the same operations. `pivots` gets the row swaps
// (LAPACK style), `row_ids` is swapped alike, `sign` takes the pivots' signs and `smallest` the
// smallest pivot size. False on a zero pivot.
template <int Rows>
bool eliminate_front(double* __restrict front, Index m, Index width, int* __restrict pivots,
                     int* __restrict row_ids, double& sign, double& smallest) {
  if constexpr (Rows > 0) m = Rows;
#pragma GCC unroll 12
  for (Index k = 0; k < kBlockColumns; ++k) {
    double* const pivot_column = front + m * k;
    Index p = k;
    double size = std::abs(pivot_column[k]);
    for (Index i = k + 1; i < m; ++i)
      if (std::abs(pivot_column[i]) > size) {
        size = std::abs(pivot_column[i]);
        p = i;
      }
    if (!(size > 0)) return false;
    smallest = std::min(smallest, size);
    pivots[k] = static_cast<int>(p);
    if (p != k) {
      for (Index j = 0; j < kBlockColumns; ++j) std::swap(front[m * j + k], front[m * j + p]);
      std::swap(row_ids[k], row_ids[p]);
    }
    const double pivot = pivot_column[k];
    if (pivot < 0) sign = -sign;
    for (Index i = k + 1; i < m; ++i) pivot_column[i] /= pivot;
    for (Index j = k + 1; j < kBlockColumns; ++j)
      subtract_multiple(front + m * j, pivot_column, k + 1, m);
  }
  for (Index j = kBlockColumns; j < width; ++j) {
    double* const column = front + m * j;
    for (Index k = 0; k < kBlockColumns; ++k)
      if (const Index p = pivots[k]; p != k) std::swap(column[k], column[p]);
    update_column<Rows>(column, front, m);
  }
  return true;
}

// z[0 … 12) = U⁻¹·z for the 12 × 12 upper triangle U of a front of `m` rows (`Rows` > 0: m at
// compile time, the loops unrolled), column by column from the last, a zero skipping its column.
template <int Rows>
inline void back_substitute(double* __restrict z, const double* __restrict u, Index m) {
  if constexpr (Rows > 0) m = Rows;
#pragma GCC unroll 12
  for (int k = kBlockColumns - 1; k >= 0; --k) {
    const double v = z[k] / u[m * k + k];
    z[k] = v;
    if (v != 0)
#pragma GCC unroll 12
      for (int i = 0; i < k; ++i) z[i] -= v * u[m * k + i];
  }
}

// target[i] = row_scale[i]·scaled[i] for i < rows.
inline void scale_rows(double* __restrict target, const double* __restrict row_scale,
                       const double* __restrict scaled, int rows) {
  for (int i = 0; i < rows; ++i) target[i] = row_scale[i] * scaled[i];
}

// target[i] = row_scale[i]·(value[i]·column_scale) for i < rows: the two scalings in the order
// the fresh path applies them.
inline void scale_both(double* __restrict target, const double* __restrict row_scale,
                       const double* __restrict value, double column_scale, int rows) {
  for (int i = 0; i < rows; ++i) target[i] = row_scale[i] * (value[i] * column_scale);
}

// z[0 … 12) −= U·x for a 12 × 12 block U of leading dimension `stride`, each row's sum formed
// from its first term on (as the dense product did).
inline void subtract_group_product(double* __restrict z, const double* __restrict u, Index stride,
                                   const double* __restrict x) {
  double sum[kBlockColumns];
  for (int i = 0; i < kBlockColumns; ++i) sum[i] = u[i] * x[0];
  for (int p = 1; p < kBlockColumns; ++p)
    for (int i = 0; i < kBlockColumns; ++i) sum[i] += u[stride * p + i] * x[p];
  for (int i = 0; i < kBlockColumns; ++i) z[i] -= sum[i];
}

}  // namespace

void BlockLU::analyze(const BlockLayout& layout) {
  layout_ = layout;
  steps_.clear();
  structurally_singular_ = false;
  n_ = kBlockColumns * layout.group_count;
  first_row_.assign(layout.rows.size(), 0);
  int total = 0;
  for (std::size_t b = 0; b < layout.rows.size(); ++b) {
    first_row_[b] = total;
    total += layout.rows[b];
  }
  if (total != n_) structurally_singular_ = true;

  // The blocks still to be merged into a front: the original ones, then those the steps leave.
  struct Active {
    int source;
    int rows;
    std::vector<int> groups;
    bool alive;
  };
  std::vector<Active> active;
  for (std::size_t b = 0; b < layout.rows.size(); ++b)
    if (layout.rows[b] > 0)
      active.push_back({-static_cast<int>(b) - 1, layout.rows[b], layout.groups[b], true});
  std::vector<char> eliminated(static_cast<std::size_t>(layout.group_count), 0);
  std::vector<char> in_front(static_cast<std::size_t>(layout.group_count), 0);

  for (int step = 0; step < layout.group_count && !structurally_singular_; ++step) {
    // The group whose front is smallest (rows × groups): a leaf of a tree, first.
    int best = -1;
    long best_cost = std::numeric_limits<long>::max();
    for (int g = 0; g < layout.group_count; ++g) {
      if (eliminated[static_cast<std::size_t>(g)]) continue;
      long rows = 0, groups = 0;
      std::vector<int> touched;
      for (const Active& a : active) {
        if (!a.alive || std::find(a.groups.begin(), a.groups.end(), g) == a.groups.end()) continue;
        rows += a.rows;
        for (int h : a.groups)
          if (!in_front[static_cast<std::size_t>(h)]) {
            in_front[static_cast<std::size_t>(h)] = 1;
            touched.push_back(h);
            ++groups;
          }
      }
      for (int h : touched) in_front[static_cast<std::size_t>(h)] = 0;
      const long cost = rows * std::max(groups, 1L);
      if (cost < best_cost) {
        best_cost = cost;
        best = g;
      }
    }
    Step s;
    s.group = best;
    std::vector<int> others;
    for (const Active& a : active)
      if (a.alive && std::find(a.groups.begin(), a.groups.end(), best) != a.groups.end())
        for (int h : a.groups)
          if (h != best && std::find(others.begin(), others.end(), h) == others.end())
            others.push_back(h);
    std::sort(others.begin(), others.end());
    s.groups.push_back(best);
    s.groups.insert(s.groups.end(), others.begin(), others.end());
    for (Active& a : active) {
      if (!a.alive || std::find(a.groups.begin(), a.groups.end(), best) == a.groups.end()) continue;
      Part part;
      part.source = a.source;
      part.first_row = s.rows;
      part.rows = a.rows;
      for (int h : a.groups)
        part.column_groups.push_back(
            static_cast<int>(std::find(s.groups.begin(), s.groups.end(), h) - s.groups.begin()));
      s.rows += a.rows;
      s.parts.push_back(std::move(part));
      a.alive = false;
    }
    eliminated[static_cast<std::size_t>(best)] = 1;
    const int left = s.rows - kBlockColumns;
    if (left < 0 || (left > 0 && others.empty())) {
      structurally_singular_ = true;
      break;
    }
    if (left > 0) active.push_back({step, left, others, true});
    for (Part& part : s.parts)
      for (int k = 0; k < static_cast<int>(s.groups.size()); ++k)
        if (std::find(part.column_groups.begin(), part.column_groups.end(), k) ==
            part.column_groups.end())
          part.zero_groups.push_back(k);
    s.front.resize(s.rows, kBlockColumns * static_cast<Index>(s.groups.size()));
    s.pivots.assign(kBlockColumns, 0);
    s.row_ids.assign(static_cast<std::size_t>(s.rows), 0);
    steps_.push_back(std::move(s));
  }

  std::vector<int> column_order;
  column_order.reserve(static_cast<std::size_t>(n_));
  for (const Step& s : steps_)
    for (int c = 0; c < kBlockColumns; ++c) column_order.push_back(kBlockColumns * s.group + c);
  column_parity_ = structurally_singular_ ? 1 : permutation_parity(column_order);
  scaling_.row.resize(n_);
  scaling_.column.resize(n_);
  rhs_.assign(steps_.size(), MatX());
  column_scaled_.resize(layout.rows.size());
  for (std::size_t b = 0; b < layout.rows.size(); ++b)
    column_scaled_[b].resize(layout.rows[b],
                             kBlockColumns * static_cast<Index>(layout.groups[b].size()));
  row_order_.reserve(static_cast<std::size_t>(n_));
  std::size_t widest = 0;
  for (const std::vector<int>& groups : layout.groups) widest = std::max(widest, groups.size());
  block_scratch_.resize(kBlockColumns * static_cast<Index>(widest));
}

BlockLU::Outcome BlockLU::factorise(const std::vector<MatX>& values, const BlockScaling* kept) {
  sign_ = 0;
  smallest_pivot_ = 0;
  if (structurally_singular_) return Outcome::singular;
  if (kept && kept->row.size() == n_ && kept->column.size() == n_) {
    // A NaN would pass the pivot tests, as it compares false (equilibrate checks the same).
    for (const MatX& v : values)
      if (!v.allFinite()) return Outcome::singular;
    if (kept != &scaling_) scaling_ = *kept;
  } else {
    kept = nullptr;
    if (!equilibrate(values)) return Outcome::singular;
  }
  double sign = column_parity_;
  smallest_pivot_ = std::numeric_limits<double>::infinity();
  row_order_.clear();
  for (Step& s : steps_) {
    assemble_front(s, kept ? &values : nullptr);
    if (!eliminate(s, sign)) return Outcome::singular;
    row_order_.insert(row_order_.end(), s.row_ids.begin(), s.row_ids.begin() + kBlockColumns);
  }
  sign_ = sign * permutation_parity(row_order_);
  return smallest_pivot_ < kBlockLuTinyPivot ? Outcome::tiny_pivot : Outcome::factorised;
}

// Each column's largest size of a block of `Rows` rows (Eigen::Dynamic: `rows`), in `largest`
// (one per column); the columns' reductions unrolled where the rows are fixed.
template <int Rows>
void column_largest(const double* values, Index rows, Index columns, double* largest) {
  const Eigen::Map<const Eigen::Matrix<double, Rows, Eigen::Dynamic>> block(values, rows, columns);
  Eigen::Map<Eigen::RowVectorXd>(largest, columns) = block.cwiseAbs().colwise().maxCoeff();
}

// scaled = values·diag(scale), and each row's largest size of it into row_largest.
template <int Rows>
void scale_columns(const double* values, Index rows, Index columns, const double* scale,
                   double* scaled, double* row_largest) {
  using Block = Eigen::Matrix<double, Rows, Eigen::Dynamic>;
  Eigen::Map<Block> result(scaled, rows, columns);
  result = Eigen::Map<const Block>(values, rows, columns) *
           Eigen::Map<const VecX>(scale, columns).asDiagonal();
  Eigen::Map<Eigen::Matrix<double, Rows, 1>>(row_largest, rows) =
      result.cwiseAbs().rowwise().maxCoeff();
}

// Equilibration by powers of two (no rounding): each column's largest entry, then each row's
// of the column-scaled matrix, near 1. Partial pivoting then compares rows of like size, and a
// pivot's size reads against 1. The column-scaled values are kept for the fronts. False where
// some entry is not finite (a NaN would pass the pivot tests, as it compares false).
bool BlockLU::equilibrate(const std::vector<MatX>& values) {
  const std::size_t blocks = layout_.rows.size();
  scaling_.column.setZero();
  // Zero, unless some entry is infinite or NaN (0·∞ is NaN).
  double probe = 0;
  double* const block_columns = block_scratch_.data();
  for (std::size_t b = 0; b < blocks; ++b) {
    const MatX& v = values[b];
    probe += (Eigen::Map<const VecX>(v.data(), v.size()).array() * 0.0).sum();
    // The blocks' usual row counts (a link's 12, a joint's 12 over two ends, a support's or a
    // free end's 6) have their reductions unrolled.
    switch (v.rows()) {
      case 12: column_largest<12>(v.data(), v.rows(), v.cols(), block_columns); break;
      case 6: column_largest<6>(v.data(), v.rows(), v.cols(), block_columns); break;
      default: column_largest<Eigen::Dynamic>(v.data(), v.rows(), v.cols(), block_columns);
    }
    const double* largest = block_columns;
    for (int group : layout_.groups[b])
      for (int c = 0; c < kBlockColumns; ++c, ++largest) {
        double& column = scaling_.column[kBlockColumns * group + c];
        column = std::max(column, *largest);
      }
  }
  if (!(probe == 0)) return false;
  for (Index j = 0; j < n_; ++j) scaling_.column[j] = power_of_two_scale(scaling_.column[j]);
  for (std::size_t b = 0; b < blocks; ++b) {
    const MatX& v = values[b];
    double* scale = block_columns;
    for (int group : layout_.groups[b])
      scale = std::copy_n(scaling_.column.data() + kBlockColumns * group, kBlockColumns, scale);
    double* const row_largest = scaling_.row.data() + first_row_[b];
    double* const scaled = column_scaled_[b].data();
    switch (v.rows()) {
      case 12:
        scale_columns<12>(v.data(), v.rows(), v.cols(), block_columns, scaled, row_largest);
        break;
      case 6:
        scale_columns<6>(v.data(), v.rows(), v.cols(), block_columns, scaled, row_largest);
        break;
      default:
        scale_columns<Eigen::Dynamic>(v.data(), v.rows(), v.cols(), block_columns, scaled,
                                      row_largest);
    }
    for (Index i = 0; i < v.rows(); ++i) row_largest[i] = power_of_two_scale(row_largest[i]);
  }
  return true;
}

// The front of step `s` from the scaled original blocks and the rows earlier steps left; every
// entry written once (the zeros where a part's rows meet none of its columns). From `unscaled`,
// an entry is (value·column scale)·row scale, as column_scaled_ and the row scales make it: the
// same bits.
void BlockLU::assemble_front(Step& s, const std::vector<MatX>* unscaled) {
  // The usual parts: a block of 12 or 6 rows, or the 6 rows an earlier step left.
  for (const Part& part : s.parts) switch (part.rows) {
      case 6: assemble_part<6>(s, part, unscaled); break;
      case 12: assemble_part<12>(s, part, unscaled); break;
      default: assemble_part<0>(s, part, unscaled);
    }
}

template <int PartRows>
void BlockLU::assemble_part(Step& s, const Part& part, const std::vector<MatX>* unscaled) {
  const Index m = s.rows;
  double* const front = s.front.data();
  const int rows = PartRows > 0 ? PartRows : part.rows;
  for (int group : part.zero_groups) {
    double* target = front + m * kBlockColumns * group + part.first_row;
    for (int c = 0; c < kBlockColumns; ++c, target += m) std::fill_n(target, rows, 0.0);
  }
  if (part.source < 0) {
    const std::size_t b = static_cast<std::size_t>(-part.source - 1);
    const double* const row_scale = scaling_.row.data() + first_row_[b];
    if (unscaled) {
      const double* value = (*unscaled)[b].data();
      for (std::size_t k = 0; k < part.column_groups.size(); ++k) {
        double* target = front + m * kBlockColumns * part.column_groups[k] + part.first_row;
        const double* const column_scale =
            scaling_.column.data() + kBlockColumns * static_cast<Index>(layout_.groups[b][k]);
        for (int c = 0; c < kBlockColumns; ++c, value += rows, target += m)
          scale_both(target, row_scale, value, column_scale[c], rows);
      }
    } else {
      const double* scaled = column_scaled_[b].data();
      for (int group : part.column_groups) {
        double* target = front + m * kBlockColumns * group + part.first_row;
        for (int c = 0; c < kBlockColumns; ++c, scaled += rows, target += m)
          scale_rows(target, row_scale, scaled, rows);
      }
    }
    for (int i = 0; i < rows; ++i)
      s.row_ids[static_cast<std::size_t>(part.first_row + i)] = first_row_[b] + i;
  } else {
    const Step& earlier = steps_[static_cast<std::size_t>(part.source)];
    const Index earlier_rows = earlier.rows;
    for (std::size_t k = 0; k < part.column_groups.size(); ++k) {
      // The rows left below the earlier front's 12 pivot rows, in its group k + 1.
      const double* left = earlier.front.data() +
                           earlier_rows * kBlockColumns * static_cast<Index>(k + 1) + kBlockColumns;
      double* target = front + m * kBlockColumns * part.column_groups[k] + part.first_row;
      for (int c = 0; c < kBlockColumns; ++c, left += earlier_rows, target += m)
        std::copy_n(left, rows, target);
    }
    for (int i = 0; i < rows; ++i)
      s.row_ids[static_cast<std::size_t>(part.first_row + i)] =
          earlier.row_ids[static_cast<std::size_t>(kBlockColumns + i)];
  }
}

// The front's elimination (eliminate_front), with its rows fixed at compile time where they
// are one of the usual counts.
bool BlockLU::eliminate(Step& s, double& sign) {
  const Index m = s.rows, width = s.front.cols();
  double* const front = s.front.data();
  int* const pivots = s.pivots.data();
  int* const row_ids = s.row_ids.data();
  // The fronts of trees and of the robots' loops: a group's 12 or 18 rows (its link's or
  // joint's block and the 6 rows left below), 24 or 30 or 36 where loops merge.
  switch (m) {
    case 12: return eliminate_front<12>(front, m, width, pivots, row_ids, sign, smallest_pivot_);
    case 18: return eliminate_front<18>(front, m, width, pivots, row_ids, sign, smallest_pivot_);
    case 24: return eliminate_front<24>(front, m, width, pivots, row_ids, sign, smallest_pivot_);
    case 30: return eliminate_front<30>(front, m, width, pivots, row_ids, sign, smallest_pivot_);
    case 36: return eliminate_front<36>(front, m, width, pivots, row_ids, sign, smallest_pivot_);
    default: return eliminate_front<0>(front, m, width, pivots, row_ids, sign, smallest_pivot_);
  }
}

void BlockLU::solve(MatX& b) const {
  const Index columns = b.cols(), n = b.rows();
  b.array().colwise() *= scaling_.row.array();
  for (std::size_t index = 0; index < steps_.size(); ++index) {
    const Step& s = steps_[index];
    const Index m = s.rows;
    MatX& y = rhs_[index];
    y.resize(m, columns);
    for (Index c = 0; c < columns; ++c) {
      double* const target = y.data() + m * c;
      for (const Part& part : s.parts) {
        const double* source =
            part.source < 0
                ? b.data() + n * c + first_row_[static_cast<std::size_t>(-part.source - 1)]
                : rhs_[static_cast<std::size_t>(part.source)].data() +
                      steps_[static_cast<std::size_t>(part.source)].rows * c + kBlockColumns;
        std::copy(source, source + part.rows, target + part.first_row);
      }
      for (Index k = 0; k < kBlockColumns; ++k)
        if (const Index p = s.pivots[static_cast<std::size_t>(k)]; p != k)
          std::swap(target[k], target[p]);
      switch (m) {
        case 12: update_column<12>(target, s.front.data(), m); break;
        case 18: update_column<18>(target, s.front.data(), m); break;
        case 24: update_column<24>(target, s.front.data(), m); break;
        default: update_column(target, s.front.data(), m);
      }
    }
  }
  for (std::size_t index = steps_.size(); index-- > 0;) {
    const Step& s = steps_[index];
    const Index m = s.rows;
    const double* const u = s.front.data();
    for (Index c = 0; c < columns; ++c) {
      double* const z = rhs_[index].data() + m * c;
      for (std::size_t k = 1; k < s.groups.size(); ++k)
        subtract_group_product(z, u + m * kBlockColumns * static_cast<Index>(k), m,
                               b.data() + n * c + kBlockColumns * s.groups[k]);
      switch (m) {
        case 12: back_substitute<12>(z, u, m); break;
        case 18: back_substitute<18>(z, u, m); break;
        case 24: back_substitute<24>(z, u, m); break;
        default: back_substitute<0>(z, u, m);
      }
      std::copy(z, z + kBlockColumns, b.data() + n * c + kBlockColumns * s.group);
    }
  }
  b.array().colwise() *= scaling_.column.array();
}

}  // namespace stiffmsa::detail
