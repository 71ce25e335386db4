// The block LU of the loaded mode's tangent (docs/theory.md §15.10).
#include "solver/block_lu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stiffmsa::detail {

namespace {

// The power of two that brings `largest` into [0.5, 1); 1 for a zero (or non-finite) size.
double power_of_two_scale(double largest) {
  if (!(largest > 0) || !std::isfinite(largest)) return 1.0;
  int exponent = 0;
  std::frexp(largest, &exponent);
  return std::ldexp(1.0, -exponent);
}

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
  row_scale_.resize(n_);
  column_scale_.resize(n_);
  rhs_.assign(steps_.size(), MatX());
}

BlockLU::Outcome BlockLU::factorise(const std::vector<MatX>& values) {
  sign_ = 0;
  smallest_pivot_ = 0;
  if (structurally_singular_) return Outcome::singular;
  const std::size_t blocks = layout_.rows.size();
  // A non-finite entry would pass the pivot tests below (NaN compares false): no factors.
  for (std::size_t b = 0; b < blocks; ++b)
    if (!values[b].allFinite()) return Outcome::singular;

  // Equilibration by powers of two (no rounding): each column's largest entry, then each row's
  // of the column-scaled matrix, near 1. Partial pivoting then compares rows of like size, and
  // a pivot's size reads against 1.
  column_scale_.setZero();
  for (std::size_t b = 0; b < blocks; ++b) {
    const MatX& v = values[b];
    for (std::size_t k = 0; k < layout_.groups[b].size(); ++k)
      for (int c = 0; c < kBlockColumns; ++c) {
        const Index j = kBlockColumns * layout_.groups[b][k] + c;
        column_scale_(j) =
            std::max(column_scale_(j),
                     v.col(kBlockColumns * static_cast<Index>(k) + c).cwiseAbs().maxCoeff());
      }
  }
  for (Index j = 0; j < n_; ++j) column_scale_(j) = power_of_two_scale(column_scale_(j));
  for (std::size_t b = 0; b < blocks; ++b) {
    const MatX& v = values[b];
    for (Index i = 0; i < layout_.rows[b]; ++i) {
      double largest = 0;
      for (std::size_t k = 0; k < layout_.groups[b].size(); ++k)
        largest = std::max(
            largest,
            (v.row(i).segment<kBlockColumns>(kBlockColumns * static_cast<Index>(k)).array() *
             column_scale_.segment<kBlockColumns>(kBlockColumns * layout_.groups[b][k])
                 .transpose()
                 .array())
                .abs()
                .maxCoeff());
      row_scale_(first_row_[b] + i) = power_of_two_scale(largest);
    }
  }

  double sign = column_parity_;
  smallest_pivot_ = std::numeric_limits<double>::infinity();
  std::vector<int> row_order;
  row_order.reserve(static_cast<std::size_t>(n_));
  for (Step& s : steps_) {
    MatX& f = s.front;
    f.setZero();
    for (const Part& part : s.parts) {
      if (part.source < 0) {
        const std::size_t b = static_cast<std::size_t>(-part.source - 1);
        const MatX& v = values[b];
        const auto rows = row_scale_.segment(first_row_[b], part.rows);
        for (std::size_t k = 0; k < part.column_groups.size(); ++k) {
          const auto columns =
              column_scale_.segment<kBlockColumns>(kBlockColumns * layout_.groups[b][k]);
          f.block(part.first_row, kBlockColumns * part.column_groups[k], part.rows,
                  kBlockColumns) +=
              rows.asDiagonal() *
              v.block(0, kBlockColumns * static_cast<Index>(k), part.rows, kBlockColumns) *
              columns.asDiagonal();
        }
        for (int i = 0; i < part.rows; ++i)
          s.row_ids[static_cast<std::size_t>(part.first_row + i)] = first_row_[b] + i;
      } else {
        const Step& earlier = steps_[static_cast<std::size_t>(part.source)];
        for (std::size_t k = 0; k < part.column_groups.size(); ++k)
          f.block(part.first_row, kBlockColumns * part.column_groups[k], part.rows,
                  kBlockColumns) +=
              earlier.front.block(kBlockColumns, kBlockColumns * static_cast<Index>(k + 1),
                                  part.rows, kBlockColumns);
        for (int i = 0; i < part.rows; ++i)
          s.row_ids[static_cast<std::size_t>(part.first_row + i)] =
              earlier.row_ids[static_cast<std::size_t>(kBlockColumns + i)];
      }
    }
    const Index m = f.rows(), w = f.cols();
    for (Index k = 0; k < kBlockColumns; ++k) {
      Index p = 0;
      const double size = f.col(k).tail(m - k).cwiseAbs().maxCoeff(&p);
      p += k;
      if (!(size > 0)) return Outcome::singular;
      smallest_pivot_ = std::min(smallest_pivot_, size);
      s.pivots[static_cast<std::size_t>(k)] = static_cast<int>(p);
      if (p != k) {
        f.row(k).swap(f.row(p));
        std::swap(s.row_ids[static_cast<std::size_t>(k)], s.row_ids[static_cast<std::size_t>(p)]);
      }
      const double pivot = f(k, k);
      if (pivot < 0) sign = -sign;
      const Index below = m - k - 1;
      f.col(k).tail(below) /= pivot;
      // The rank-one update column by column (axpy): a general product's blocking costs more
      // than the update itself at these sizes.
      for (Index j = k + 1; j < w; ++j)
        if (const double u = f(k, j); u != 0) f.col(j).tail(below) -= u * f.col(k).tail(below);
    }
    row_order.insert(row_order.end(), s.row_ids.begin(), s.row_ids.begin() + kBlockColumns);
  }
  sign_ = sign * permutation_parity(row_order);
  return smallest_pivot_ < kBlockLuTinyPivot ? Outcome::tiny_pivot : Outcome::factorised;
}

void BlockLU::solve(MatX& b) const {
  const Index columns = b.cols();
  b.array().colwise() *= row_scale_.array();
  for (std::size_t index = 0; index < steps_.size(); ++index) {
    const Step& s = steps_[index];
    MatX& y = rhs_[index];
    y.resize(s.rows, columns);
    for (const Part& part : s.parts) {
      if (part.source < 0)
        y.middleRows(part.first_row, part.rows) =
            b.middleRows(first_row_[static_cast<std::size_t>(-part.source - 1)], part.rows);
      else
        y.middleRows(part.first_row, part.rows) =
            rhs_[static_cast<std::size_t>(part.source)].bottomRows(part.rows);
    }
    for (Index k = 0; k < kBlockColumns; ++k)
      if (s.pivots[static_cast<std::size_t>(k)] != k)
        y.row(k).swap(y.row(s.pivots[static_cast<std::size_t>(k)]));
    // L's columns applied one by one (small sizes: no blocked triangular solve or product).
    for (Index k = 0; k < kBlockColumns; ++k)
      for (Index c = 0; c < columns; ++c)
        if (const double v = y(k, c); v != 0)
          y.col(c).tail(s.rows - k - 1) -= v * s.front.col(k).tail(s.rows - k - 1);
  }
  for (std::size_t index = steps_.size(); index-- > 0;) {
    const Step& s = steps_[index];
    auto z = rhs_[index].topRows(kBlockColumns);
    for (std::size_t k = 1; k < s.groups.size(); ++k)
      z.noalias() -=
          s.front.block(0, kBlockColumns * static_cast<Index>(k), kBlockColumns, kBlockColumns)
              .lazyProduct(b.middleRows(kBlockColumns * s.groups[k], kBlockColumns));
    for (Index k = kBlockColumns; k-- > 0;)
      for (Index c = 0; c < columns; ++c) {
        const double v = z(k, c) / s.front(k, k);
        z(k, c) = v;
        if (v != 0) z.col(c).head(k) -= v * s.front.col(k).head(k);
      }
    b.middleRows(kBlockColumns * s.group, kBlockColumns) = z;
  }
  b.array().colwise() *= column_scale_.array();
}

}  // namespace stiffmsa::detail
