#include <cmath>

#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

namespace {
// The power of two nearest to 1/sqrt(m) (m > 0), so that scaling is exact in binary.
double inverse_sqrt_power_of_two(double m) {
  if (!(m > 0) || !std::isfinite(m)) return 1.0;
  return std::exp2(-std::round(0.5 * std::log2(m)));
}
}  // namespace

Equilibration equilibrate(const SparseMatrix& a, int iterations) {
  const Index n = a.rows();
  Equilibration s{VecX::Ones(n), VecX::Ones(a.cols())};
  VecX row_max(n), column_max(a.cols());
  // Ruiz's iteration: alternately divide rows and columns by the square root of their
  // largest scaled entry; it converges to every row and column having a largest entry of 1.
  for (int it = 0; it < iterations; ++it) {
    row_max.setZero();
    column_max.setZero();
    for (Index j = 0; j < a.outerSize(); ++j)
      for (SparseMatrix::InnerIterator e(a, j); e; ++e) {
        const double v = std::abs(e.value()) * s.row(e.row()) * s.column(j);
        row_max(e.row()) = std::max(row_max(e.row()), v);
        column_max(j) = std::max(column_max(j), v);
      }
    bool changed = false;
    for (Index i = 0; i < n; ++i) {
      const double f = inverse_sqrt_power_of_two(row_max(i));
      changed |= f != 1.0;
      s.row(i) *= f;
    }
    for (Index j = 0; j < a.cols(); ++j) {
      const double f = inverse_sqrt_power_of_two(column_max(j));
      changed |= f != 1.0;
      s.column(j) *= f;
    }
    if (!changed) break;
  }
  return s;
}

}  // namespace stiffmsa::detail
