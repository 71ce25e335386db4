#include <bit>
#include <cmath>
#include <cstdint>

#include "solver/sparse_solver.hpp"

namespace stiffmsa::detail {

namespace {
// For m in [2^(e−1), 2^e): 2^(−⌊e/2⌋), which brings m·f² into [½, 2). A power of two, so that
// scaling is exact in binary; read from and written to the exponent bits (this runs for every
// row and column of every sweep, where frexp and ldexp calls were most of the time).
double inverse_sqrt_power_of_two(double m) {
  if (!(m > 0) || !std::isfinite(m)) return 1.0;
  const auto biased = static_cast<int>((std::bit_cast<std::uint64_t>(m) >> 52) & 0x7ff);
  int exponent = biased - 1022;
  if (biased == 0) std::frexp(m, &exponent);  // subnormal
  const int power = -(exponent >> 1);         // −⌊e/2⌋, in [−512, 537]
  return std::bit_cast<double>(static_cast<std::uint64_t>(power + 1023) << 52);
}
}  // namespace

Equilibration equilibrate(const SparseMatrix& a, const Equilibration* start, int iterations) {
  const Index n = a.rows();
  Equilibration s = start ? *start : Equilibration{VecX::Ones(n), VecX::Ones(a.cols())};
  VecX row_max(n), column_max(a.cols());
  // Ruiz's iteration: alternately divide rows and columns by the square root of their
  // largest scaled entry; it converges to every row and column having a largest entry near 1.
  for (int it = 0; it < iterations; ++it) {
    row_max.setZero();
    column_max.setZero();
    for (Index j = 0; j < a.outerSize(); ++j) {
      const double column_scale = s.column(j);
      double largest = 0;
      for (SparseMatrix::InnerIterator e(a, j); e; ++e) {
        const double v = std::abs(e.value()) * s.row(e.row()) * column_scale;
        row_max(e.row()) = std::max(row_max(e.row()), v);
        largest = std::max(largest, v);
      }
      column_max(j) = largest;
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
