#pragma once
// Sparse direct solvers behind one interface, and the equilibrated, refined solve that the
// analyses use. The mixed system holds stiffness entries near 1e9 beside identity entries of
// 1, so it is scaled before factorisation; residuals are measured on the unscaled system.
#include <memory>
#include <optional>
#include <vector>

#include "assembly/assembler.hpp"
#include "stiffmsa/solver_kind.hpp"
#include "tolerances.hpp"

namespace stiffmsa::detail {

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  // Symbolic analysis (ordering) of a pattern; kept while only values change.
  virtual void analyze(const SparseMatrix& a) = 0;
  // Numeric factorisation; false when a pivot is exactly zero (structurally singular).
  virtual bool factorize(const SparseMatrix& a) = 0;
  // In-place solves with A or Aᵀ for every column of b.
  virtual void solve(MatX& b) const = 0;
  virtual void solve_transposed(MatX& b) const = 0;
  virtual const char* name() const = 0;
  // Whether the last factorisation kept an earlier matrix's pivot order (KLU, see KluLU).
  virtual bool reused_pivot_order() const { return false; }
  // The sign of the last factorised matrix's determinant (+1 or −1; 0 where a pivot is zero).
  virtual double determinant_sign() const = 0;
  // The next factorisation becomes the reference whose pivot order later ones keep (KLU), as
  // after a pattern analysis, without analysing the pattern again.
  virtual void renew_reference() {}
  // Where the last factorisation was made afresh (the reference's pivot order did not suit it),
  // it becomes the reference (KLU): for a sequence of matrices that drift away from the first.
  virtual void adopt_last_as_reference() {}
};

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind);

// Hager's estimate of ‖A⁻¹‖₁ from a factorisation of the n×n matrix A (Higham's refinement,
// LAPACK xLACON, with Higham's alternating-sign test vector as a safeguard); +inf when a solve
// overflows.
double estimate_inverse_norm1(const LinearSolver& lu, Index n);
// 1/(‖A‖₁·est‖A⁻¹‖₁) from a factorisation of A; 0 where the estimate overflows or A is zero.
double estimate_reciprocal_condition(const LinearSolver& factors, const SparseMatrix& a);

// Row and column scaling by powers of two (so scaling itself adds no rounding) that brings
// every row and column of |A| to a largest entry near 1. From `start` where given (the scaling
// of a matrix of like magnitudes: one checking sweep instead of five or six).
struct Equilibration {
  VecX row, column;
};
Equilibration equilibrate(const SparseMatrix& a, const Equilibration* start = nullptr,
                          int iterations = 8);

struct BackwardError {
  double normwise = 0;       // ‖b − A·x‖∞ / (‖A‖∞·‖x‖∞ + ‖b‖∞)
  double componentwise = 0;  // max_i |b − A·x|_i / (|A|·|x| + |b|)_i
};

class SparseColumns;

// A factorised system: scaling, factorisation, condition estimate and refined solves. The
// first matrix factorised after a pattern analysis is the reference: later matrices start
// their equilibration from its scaling, and KLU reuses its pivot order where that stays
// stable (see KluLU). So a matrix's factors depend on it and on the reference only.
class FactorizedSystem {
 public:
  explicit FactorizedSystem(SolverKind kind);

  // Analyses the pattern on the first call, or when the pattern changes.
  // Returns false when the matrix is singular to working precision (exact zero pivot or
  // reciprocal condition below `singular_rcond`).
  bool factorize(const SparseMatrix& a, double singular_rcond);

  double reciprocal_condition() const { return rcond_; }
  const char* solver_name() const { return solver_->name(); }
  bool reused_pivot_order() const { return solver_->reused_pivot_order(); }

  // Solves A·X = B. Where some column's normwise backward error over the reciprocal condition
  // exceeds kRefineAbove (a heuristic, not a bound: the error is of the unscaled system, the
  // condition of the scaled one), every column is refined, at most `refinement_steps` times;
  // `relative_residual` gets the largest backward error over the columns.
  // B is taken by value: its storage becomes the solution (move it in where it is not needed
  // after), and only its nonzeros are kept for the residuals.
  MatX solve(MatX b, int refinement_steps, double& relative_residual) const;

 private:
  // y ← S_c·Â⁻¹·S_r·y, in place.
  void apply_inverse(MatX& y) const;
  // Iterative refinement of x with residuals accumulated in extended precision; `error` gets
  // each column's final backward errors.
  void refine(const SparseColumns& b, int steps, MatX& x, std::vector<BackwardError>& error) const;

  std::unique_ptr<LinearSolver> solver_;
  const SparseMatrix* a_ = nullptr;
  double a_norm_inf_ = 0;
  SparseMatrix scaled_;  // Â = S_r·A·S_c; its pattern is the one analysed
  Equilibration scaling_;
  std::optional<Equilibration> reference_scaling_;
  bool analyzed_ = false;
  double rcond_ = 0;
};

// ‖b − A·x‖∞ / (‖A‖∞·‖x‖∞ + ‖b‖∞), per column, the largest.
double relative_residual(const SparseMatrix& a, const MatX& x, const MatX& b);

// That ratio from its norms (residual finite and ≥ 0): 0 for a zero residual, +inf where the
// denominator vanishes and the residual does not.
double normwise_backward_error(double residual_norm, double a_norm_inf, double x_norm_inf,
                               double b_norm_inf);

}  // namespace stiffmsa::detail
