#include "solver/sparse_solver.hpp"

#include <Eigen/SparseLU>
#include <cmath>

#include "stiffmsa/config.hpp"
#if STIFFMSA_HAVE_SUITESPARSE
#include <klu.h>
#include <umfpack.h>
#endif

namespace stiffmsa::detail {

namespace {

// Eigen's supernodal LU with COLAMD ordering and partial pivoting.
class EigenSparseLU final : public LinearSolver {
 public:
  void analyze(const SparseMatrix& a) override { lu_.analyzePattern(a); }
  bool factorize(const SparseMatrix& a) override {
    lu_.factorize(a);
    return lu_.info() == Eigen::Success;
  }
  void solve(MatX& b) const override { b = lu_.solve(b); }
  void solve_transposed(MatX& b) const override {
    // SparseLU's transpose view is not const-qualified.
    b = const_cast<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>&>(lu_).transpose().solve(b);
  }
  const char* name() const override { return "sparse_lu"; }

 private:
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu_;
};

#if STIFFMSA_HAVE_SUITESPARSE
// UMFPACK: multifrontal LU; its symbolic object survives numeric refactorisations. The
// symbolic analysis sees the pattern only: given values, UMFPACK would let the first matrix it
// saw steer its strategy, and a sweep's results would depend on which pose came first.
class UmfpackLU final : public LinearSolver {
 public:
  UmfpackLU() { umfpack_di_defaults(control_); }
  ~UmfpackLU() override { release(); }
  void analyze(const SparseMatrix& a) override {
    release();
    const int status = umfpack_di_symbolic(static_cast<int>(a.rows()), static_cast<int>(a.cols()),
                                           a.outerIndexPtr(), a.innerIndexPtr(), nullptr,
                                           &symbolic_, control_, nullptr);
    if (status != UMFPACK_OK) throw Error("UMFPACK symbolic analysis failed (status " + std::to_string(status) + ")");
  }
  bool factorize(const SparseMatrix& a) override {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    a_ = &a;
    const int status = umfpack_di_numeric(a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr(),
                                          symbolic_, &numeric_, control_, nullptr);
    return status == UMFPACK_OK;
  }
  void solve(MatX& b) const override { run(b, UMFPACK_A); }
  void solve_transposed(MatX& b) const override { run(b, UMFPACK_At); }
  const char* name() const override { return "umfpack"; }

 private:
  void run(MatX& b, int system) const {
    VecX x(b.rows());
    for (Index c = 0; c < b.cols(); ++c) {
      const VecX rhs = b.col(c);
      umfpack_di_solve(system, a_->outerIndexPtr(), a_->innerIndexPtr(), a_->valuePtr(), x.data(),
                       rhs.data(), numeric_, control_, nullptr);
      b.col(c) = x;
    }
  }
  void release() {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
  }
  double control_[UMFPACK_CONTROL];
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  const SparseMatrix* a_ = nullptr;
};

// KLU: left-looking LU after a block triangular form. Its default pivot tolerance (0.001)
// prefers the diagonal and loses digits on long chains; full partial pivoting is used here.
class KluLU final : public LinearSolver {
 public:
  KluLU() {
    klu_defaults(&common_);
    common_.tol = 1.0;
  }
  ~KluLU() override { release(); }
  void analyze(const SparseMatrix& a) override {
    release();
    n_ = static_cast<int>(a.rows());
    symbolic_ = klu_analyze(n_, const_cast<int*>(a.outerIndexPtr()), const_cast<int*>(a.innerIndexPtr()), &common_);
    if (!symbolic_) throw Error("KLU symbolic analysis failed (status " + std::to_string(common_.status) + ")");
  }
  bool factorize(const SparseMatrix& a) override {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    numeric_ = klu_factor(const_cast<int*>(a.outerIndexPtr()), const_cast<int*>(a.innerIndexPtr()),
                          const_cast<double*>(a.valuePtr()), symbolic_, &common_);
    return numeric_ != nullptr && common_.status == KLU_OK;
  }
  void solve(MatX& b) const override {
    klu_solve(symbolic_, numeric_, n_, static_cast<int>(b.cols()), b.data(), &common_);
  }
  void solve_transposed(MatX& b) const override {
    klu_tsolve(symbolic_, numeric_, n_, static_cast<int>(b.cols()), b.data(), &common_);
  }
  const char* name() const override { return "klu"; }

 private:
  void release() {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
  }
  mutable klu_common common_;
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
  int n_ = 0;
};
#endif

double norm_inf(const SparseMatrix& a) {
  VecX row_sums = VecX::Zero(a.rows());
  for (Index j = 0; j < a.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(a, j); e; ++e) row_sums(e.row()) += std::abs(e.value());
  return a.rows() ? row_sums.maxCoeff() : 0.0;
}

double norm_1(const SparseMatrix& a) {
  double best = 0;
  for (Index j = 0; j < a.outerSize(); ++j) {
    double sum = 0;
    for (SparseMatrix::InnerIterator e(a, j); e; ++e) sum += std::abs(e.value());
    best = std::max(best, sum);
  }
  return best;
}

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind) {
  switch (kind) {
    case SolverKind::sparse_lu: return std::make_unique<EigenSparseLU>();
#if STIFFMSA_HAVE_SUITESPARSE
    case SolverKind::umfpack: return std::make_unique<UmfpackLU>();
    case SolverKind::klu: return std::make_unique<KluLU>();
#else
    case SolverKind::umfpack:
    case SolverKind::klu: break;
#endif
  }
  throw UsageError(std::string("the solver '") + to_string(kind) + "' is not built into this stiffmsa");
}

double relative_residual(const SparseMatrix& a, const MatX& x, const MatX& b) {
  const MatX r = b - a * x;
  const double a_norm = norm_inf(a);
  double worst = 0;
  for (Index c = 0; c < x.cols(); ++c) {
    const double denominator = a_norm * x.col(c).lpNorm<Eigen::Infinity>() + b.col(c).lpNorm<Eigen::Infinity>();
    const double numerator = r.col(c).lpNorm<Eigen::Infinity>();
    if (numerator > 0) worst = std::max(worst, denominator > 0 ? numerator / denominator : INFINITY);
  }
  return worst;
}

FactorizedSystem::FactorizedSystem(SolverKind kind) : solver_(make_linear_solver(kind)) {}

bool FactorizedSystem::factorize(const SparseMatrix& a, double singular_rcond) {
  a_ = &a;
  scaling_ = equilibrate(a);
  scaled_ = a;
  for (Index j = 0; j < scaled_.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(scaled_, j); e; ++e)
      e.valueRef() *= scaling_.row(e.row()) * scaling_.column(j);
  const bool same_pattern =
      analyzed_ && std::equal(analyzed_outer_.begin(), analyzed_outer_.end(), a.outerIndexPtr(),
                              a.outerIndexPtr() + a.outerSize() + 1) &&
      analyzed_outer_.size() == static_cast<std::size_t>(a.outerSize()) + 1 &&
      std::equal(analyzed_inner_.begin(), analyzed_inner_.end(), a.innerIndexPtr(),
                 a.innerIndexPtr() + a.nonZeros()) &&
      analyzed_inner_.size() == static_cast<std::size_t>(a.nonZeros());
  if (!same_pattern) {
    solver_->analyze(scaled_);
    analyzed_outer_.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1);
    analyzed_inner_.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
    analyzed_ = true;
  }
  rcond_ = 0;
  if (!solver_->factorize(scaled_)) return false;
  const double inverse_norm = estimate_inverse_norm1(*solver_, scaled_.rows());
  const double a_norm = norm_1(scaled_);
  rcond_ = (std::isfinite(inverse_norm) && inverse_norm > 0 && a_norm > 0) ? 1.0 / (a_norm * inverse_norm) : 0.0;
  return rcond_ >= singular_rcond;
}

double estimate_inverse_norm1(const LinearSolver& lu, Index n) {
  if (n == 0) return 0;
  MatX x = MatX::Constant(n, 1, 1.0 / static_cast<double>(n));
  double estimate = 0;
  Index previous_j = -1;
  for (int iteration = 0; iteration < 5; ++iteration) {
    MatX y = x;
    lu.solve(y);
    const double norm = y.lpNorm<1>();
    if (!std::isfinite(norm)) return INFINITY;
    if (iteration > 0 && norm <= estimate) break;
    estimate = norm;
    MatX sign(n, 1);
    for (Index i = 0; i < n; ++i) sign(i) = y(i) >= 0 ? 1.0 : -1.0;
    lu.solve_transposed(sign);
    Index j = 0;
    sign.col(0).cwiseAbs().maxCoeff(&j);
    if (iteration > 0 && (j == previous_j || std::abs(sign(j)) <= (sign.transpose() * x)(0, 0))) break;
    previous_j = j;
    x.setZero();
    x(j) = 1.0;
  }
  MatX alternating(n, 1);
  for (Index i = 0; i < n; ++i)
    alternating(i) = (i % 2 ? -1.0 : 1.0) * (1.0 + static_cast<double>(i) / std::max<Index>(n - 1, 1));
  lu.solve(alternating);
  const double alternative = 2.0 * alternating.lpNorm<1>() / (3.0 * static_cast<double>(n));
  if (!std::isfinite(alternative)) return INFINITY;
  return std::max(estimate, alternative);
}

MatX FactorizedSystem::solve_once(const MatX& b) const {
  MatX y = scaling_.row.asDiagonal() * b;
  solver_->solve(y);
  return scaling_.column.asDiagonal() * y;
}

namespace {
// b − A·x accumulated in extended precision: refinement then converges to the solution as
// exactly as double can hold it, where a residual in double would stall at cond(A)·ε.
MatX extended_residual(const SparseMatrix& a, const MatX& x, const MatX& b) {
  MatX r(b.rows(), b.cols());
  std::vector<long double> sum(static_cast<std::size_t>(b.rows()));
  for (Index c = 0; c < b.cols(); ++c) {
    for (Index i = 0; i < b.rows(); ++i) sum[static_cast<std::size_t>(i)] = b(i, c);
    for (Index j = 0; j < a.outerSize(); ++j) {
      const long double xj = x(j, c);
      if (xj == 0) continue;
      for (SparseMatrix::InnerIterator e(a, j); e; ++e)
        sum[static_cast<std::size_t>(e.row())] -= static_cast<long double>(e.value()) * xj;
    }
    for (Index i = 0; i < b.rows(); ++i) r(i, c) = static_cast<double>(sum[static_cast<std::size_t>(i)]);
  }
  return r;
}
}  // namespace

MatX FactorizedSystem::solve(const MatX& b, int refinement_steps, double& residual) const {
  MatX x = solve_once(b);
  residual = relative_residual(*a_, x, b);
  for (int step = 0; step < refinement_steps && residual > 0; ++step) {
    const MatX candidate = x + solve_once(extended_residual(*a_, x, b));
    const double candidate_residual = relative_residual(*a_, candidate, b);
    if (!(candidate_residual <= residual)) break;
    const bool stalled = candidate_residual > 0.5 * residual;
    x = candidate;
    residual = candidate_residual;
    if (stalled) break;
  }
  return x;
}

}  // namespace stiffmsa::detail
