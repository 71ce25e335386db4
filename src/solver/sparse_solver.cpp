#include "solver/sparse_solver.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "solver/blas_lock.hpp"
#include "stiffmsa/config.hpp"
#if STIFFMSA_HAVE_SUITESPARSE
#include <klu.h>
#include <umfpack.h>
#endif

namespace stiffmsa::detail {

std::mutex& blas_mutex() {
  static std::mutex mutex;
  return mutex;
}

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
    b = const_cast<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>&>(lu_)
            .transpose()
            .solve(b);
  }
  const char* name() const override { return "sparse_lu"; }
  double determinant_sign() const override {
    // SparseLU's determinant queries are not const-qualified.
    return const_cast<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>&>(lu_)
        .signDeterminant();
  }

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
    if (status != UMFPACK_OK)
      throw Error("UMFPACK symbolic analysis failed (status " + std::to_string(status) + ")");
  }
  bool factorize(const SparseMatrix& a) override {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    a_ = &a;
    const std::lock_guard blas(blas_mutex());
    const int status = umfpack_di_numeric(a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr(),
                                          symbolic_, &numeric_, control_, nullptr);
    return status == UMFPACK_OK;
  }
  void solve(MatX& b) const override { run(b, UMFPACK_A); }
  void solve_transposed(MatX& b) const override { run(b, UMFPACK_At); }
  const char* name() const override { return "umfpack"; }
  double determinant_sign() const override {
    double mantissa = 0;
    double exponent = 0;
    umfpack_di_get_determinant(&mantissa, &exponent, numeric_, nullptr);
    return mantissa > 0 ? 1.0 : mantissa < 0 ? -1.0 : 0.0;
  }

 private:
  void run(MatX& b, int system) const {
    VecX x(b.rows());
    const std::lock_guard blas(blas_mutex());
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
// KLU's own row scaling is off: the matrix arrives equilibrated by powers of two, and a second,
// inexact scaling would only add rounding.
//
// The first factorisation after an analysis fixes the pivot order (a workspace's reference
// model); later ones reuse it (klu_refactor: no pivot search and no depth-first searches,
// 2.5× faster on the example robots) while the reused pivots still pass threshold partial
// pivoting with tolerance 0.1 (UMFPACK's default; every multiplier |l_ij| ≤ 10, where the
// reference's own partial pivoting had ≤ 1) and KLU's reciprocal pivot growth of U stays
// within 10× of the reference's. A matrix that fails either, or meets a zero pivot, is
// factorised afresh. Which factorisation a matrix gets depends on it and the reference only,
// never on the matrices in between.
class KluLU final : public LinearSolver {
 public:
  static constexpr double kMaxMultiplier = 10;
  static constexpr double kMaxGrowthLoss = 10;

  KluLU() {
    klu_defaults(&common_);
    common_.tol = 1.0;
    common_.scale = -1;
  }
  ~KluLU() override { release(); }
  void analyze(const SparseMatrix& a) override {
    release();
    n_ = static_cast<int>(a.rows());
    symbolic_ = klu_analyze(n_, const_cast<int*>(a.outerIndexPtr()),
                            const_cast<int*>(a.innerIndexPtr()), &common_);
    if (!symbolic_)
      throw Error("KLU symbolic analysis failed (status " + std::to_string(common_.status) + ")");
    reference_state_ = Reference::none_yet;
  }
  bool factorize(const SparseMatrix& a) override {
    last_ = &a;
    int* const ap = const_cast<int*>(a.outerIndexPtr());
    int* const ai = const_cast<int*>(a.innerIndexPtr());
    double* const ax = const_cast<double*>(a.valuePtr());
    if (reference_state_ == Reference::fixed) {
      reused_ = klu_refactor(ap, ai, ax, symbolic_, reference_, &common_) &&
                common_.status == KLU_OK && multipliers_within_threshold() &&
                klu_rgrowth(ap, ai, ax, symbolic_, reference_, &common_) &&
                common_.rgrowth * kMaxGrowthLoss >= reference_growth_;
      if (reused_) {
        active_ = reference_;
        if (fresh_) klu_free_numeric(&fresh_, &common_);
        return true;
      }
      return factorize_afresh(ap, ai, ax, fresh_);
    }
    reused_ = false;
    const bool ok = factorize_afresh(ap, ai, ax, reference_);
    if (reference_state_ == Reference::none_yet) {
      reference_state_ = ok && klu_rgrowth(ap, ai, ax, symbolic_, reference_, &common_)
                             ? Reference::fixed
                             : Reference::unusable;
      reference_growth_ = common_.rgrowth;
    }
    return ok;
  }
  void solve(MatX& b) const override {
    klu_solve(symbolic_, active_, n_, static_cast<int>(b.cols()), b.data(), &common_);
  }
  void solve_transposed(MatX& b) const override {
    klu_tsolve(symbolic_, active_, n_, static_cast<int>(b.cols()), b.data(), &common_);
  }
  const char* name() const override { return "klu"; }
  bool reused_pivot_order() const override { return reused_; }
  void renew_reference() override { reference_state_ = Reference::none_yet; }
  void adopt_last_as_reference() override {
    if (reused_ || !active_ || !last_) return;
    int* const ap = const_cast<int*>(last_->outerIndexPtr());
    int* const ai = const_cast<int*>(last_->innerIndexPtr());
    double* const ax = const_cast<double*>(last_->valuePtr());
    // A reference that failed (a singular first matrix, a pivot growth KLU could not measure)
    // is replaced by the next factorisation that succeeds, so that reuse is not lost for good.
    if (reference_state_ == Reference::unusable) {
      if (active_ == reference_ && klu_rgrowth(ap, ai, ax, symbolic_, reference_, &common_)) {
        reference_state_ = Reference::fixed;
        reference_growth_ = common_.rgrowth;
      }
      return;
    }
    if (reference_state_ != Reference::fixed || !fresh_ || active_ != fresh_) return;
    if (!klu_rgrowth(ap, ai, ax, symbolic_, fresh_, &common_)) return;
    std::swap(reference_, fresh_);
    reference_growth_ = common_.rgrowth;
  }
  // P·A·Q = L·U with L's diagonal of ones: det A = det P · det Q · Π U_kk (KLU's own row
  // scaling, which would add positive factors, is off).
  double determinant_sign() const override {
    if (!active_) return 0;
    const auto* diagonal = static_cast<const double*>(active_->Udiag);
    double sign = 1;
    for (int k = 0; k < n_; ++k) {
      if (diagonal[k] == 0) return 0;
      if (diagonal[k] < 0) sign = -sign;
    }
    return sign * permutation_sign(active_->Pnum) * permutation_sign(symbolic_->Q);
  }
  // The entries of L + U that KLU's ordering predicts, before pivoting.
  double predicted_factor_entries() const { return symbolic_->lnz + symbolic_->unz; }

 private:
  // none_yet: the next factorisation is the reference; unusable: the reference failed, so
  // every matrix is factorised afresh.
  enum class Reference { none_yet, fixed, unusable };

  // +1 for an even permutation, −1 for an odd one: each cycle of length c is c − 1 swaps.
  double permutation_sign(const int* permutation) const {
    std::vector<char> visited(static_cast<std::size_t>(n_), 0);
    double sign = 1;
    for (int start = 0; start < n_; ++start) {
      if (visited[static_cast<std::size_t>(start)]) continue;
      int length = 0;
      for (int k = start; !visited[static_cast<std::size_t>(k)]; k = permutation[k]) {
        visited[static_cast<std::size_t>(k)] = 1;
        ++length;
      }
      if (length % 2 == 0) sign = -sign;
    }
    return sign;
  }

  bool multipliers_within_threshold() {
    // klu_extract writes L only with its column starts and row indices too.
    const auto entries = static_cast<std::size_t>(reference_->lnz);
    multipliers_.resize(entries);
    multiplier_rows_.resize(entries);
    multiplier_starts_.resize(static_cast<std::size_t>(n_) + 1);
    if (!klu_extract(reference_, symbolic_, multiplier_starts_.data(), multiplier_rows_.data(),
                     multipliers_.data(), nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
                     nullptr, nullptr, nullptr, nullptr, &common_))
      return false;
    for (double l : multipliers_)
      if (!(std::abs(l) <= kMaxMultiplier)) return false;
    return true;
  }
  bool factorize_afresh(int* ap, int* ai, double* ax, klu_numeric*& numeric) {
    if (numeric) klu_free_numeric(&numeric, &common_);
    numeric = klu_factor(ap, ai, ax, symbolic_, &common_);
    active_ = numeric;
    return numeric != nullptr && common_.status == KLU_OK;
  }
  void release() {
    if (reference_) klu_free_numeric(&reference_, &common_);
    if (fresh_) klu_free_numeric(&fresh_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
    active_ = nullptr;
  }
  mutable klu_common common_;
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* reference_ = nullptr;  // holds the fixed pivot order
  klu_numeric* fresh_ = nullptr;      // a matrix the fixed pivots did not suit
  klu_numeric* active_ = nullptr;     // the factorisation of the last matrix
  Reference reference_state_ = Reference::none_yet;
  double reference_growth_ = 0;
  const SparseMatrix* last_ = nullptr;  // the matrix factorised last
  bool reused_ = false;
  std::vector<double> multipliers_;  // L of a refactorisation, to check
  std::vector<int> multiplier_rows_, multiplier_starts_;
  int n_ = 0;
};
#endif

// Chooses the backend when it sees the pattern: KLU where its ordering predicts small factors
// (robots and chains, where it is the fastest by 1.5–5×), Eigen's SparseLU where KLU's ordering
// of A + Aᵀ would fill in (a building frame: 47× the entries of A predicted, and 30× the time
// of SparseLU).
class AutomaticLU final : public LinearSolver {
 public:
  static constexpr double kMaxKluFill = 10;

  void analyze(const SparseMatrix& a) override {
#if STIFFMSA_HAVE_SUITESPARSE
    auto klu = std::make_unique<KluLU>();
    klu->analyze(a);
    if (klu->predicted_factor_entries() <= kMaxKluFill * static_cast<double>(a.nonZeros())) {
      chosen_ = std::move(klu);
      return;
    }
#endif
    chosen_ = std::make_unique<EigenSparseLU>();
    chosen_->analyze(a);
  }
  bool factorize(const SparseMatrix& a) override { return chosen_->factorize(a); }
  void solve(MatX& b) const override { chosen_->solve(b); }
  void solve_transposed(MatX& b) const override { chosen_->solve_transposed(b); }
  const char* name() const override { return chosen_ ? chosen_->name() : "auto"; }
  bool reused_pivot_order() const override { return chosen_ && chosen_->reused_pivot_order(); }
  double determinant_sign() const override { return chosen_ ? chosen_->determinant_sign() : 0; }
  void renew_reference() override {
    if (chosen_) chosen_->renew_reference();
  }
  void adopt_last_as_reference() override {
    if (chosen_) chosen_->adopt_last_as_reference();
  }

 private:
  std::unique_ptr<LinearSolver> chosen_;
};

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
    case SolverKind::automatic: return std::make_unique<AutomaticLU>();
    case SolverKind::sparse_lu: return std::make_unique<EigenSparseLU>();
#if STIFFMSA_HAVE_SUITESPARSE
    case SolverKind::umfpack: return std::make_unique<UmfpackLU>();
    case SolverKind::klu: return std::make_unique<KluLU>();
#else
    case SolverKind::umfpack:
    case SolverKind::klu: break;
#endif
  }
  throw UsageError(std::string("the solver '") + to_string(kind) +
                   "' is not built into this stiffmsa");
}

FactorizedSystem::FactorizedSystem(SolverKind kind) : solver_(make_linear_solver(kind)) {}

namespace {
bool same_pattern(const SparseMatrix& a, const SparseMatrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
         std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}
}  // namespace

bool FactorizedSystem::factorize(const SparseMatrix& a, double singular_rcond) {
  a_ = &a;
  a_norm_inf_ = norm_inf(a);
  const bool reanalyse = !analyzed_ || !same_pattern(a, scaled_);
  if (reanalyse) {
    scaled_ = a;
    scaled_.makeCompressed();
    reference_scaling_.reset();
  }
  scaling_ = equilibrate(a, reference_scaling_ ? &*reference_scaling_ : nullptr);
  if (!reference_scaling_) reference_scaling_ = scaling_;
  for (Index j = 0; j < a.outerSize(); ++j) {
    SparseMatrix::InnerIterator target(scaled_, j);
    for (SparseMatrix::InnerIterator e(a, j); e; ++e, ++target)
      target.valueRef() = e.value() * scaling_.row(e.row()) * scaling_.column(j);
  }
  if (reanalyse) {
    analyzed_ = false;  // stays so if the analysis throws: scaled_ already has the new pattern
    solver_->analyze(scaled_);
    analyzed_ = true;
  }
  rcond_ = 0;
  if (!solver_->factorize(scaled_)) return false;
  rcond_ = estimate_reciprocal_condition(*solver_, scaled_);
  return rcond_ >= singular_rcond;
}

double estimate_reciprocal_condition(const LinearSolver& factors, const SparseMatrix& a) {
  const double inverse_norm = estimate_inverse_norm1(factors, a.rows());
  const double a_norm = norm_1(a);
  return (std::isfinite(inverse_norm) && inverse_norm > 0 && a_norm > 0)
             ? 1.0 / (a_norm * inverse_norm)
             : 0.0;
}

double estimate_inverse_norm1(const LinearSolver& lu, Index n) {
  if (n == 0) return 0;
  // Hager's start x = e/n and Higham's alternating vector go through one solve together: a
  // solve's fixed cost is most of it on the robots' small systems.
  MatX start(n, 2);
  start.col(0).setConstant(1.0 / static_cast<double>(n));
  for (Index i = 0; i < n; ++i)
    start(i, 1) = (i % 2 ? -1.0 : 1.0) *
                  (1.0 + static_cast<double>(i) / static_cast<double>(std::max<Index>(n - 1, 1)));
  lu.solve(start);
  const double alternative = 2.0 * start.col(1).lpNorm<1>() / (3.0 * static_cast<double>(n));
  if (!std::isfinite(alternative)) return INFINITY;
  MatX x(n, 1), y = start.col(0), z(n, 1);
  double estimate = 0;
  Index previous_j = -1;
  for (int iteration = 0; iteration < 5; ++iteration) {
    if (iteration > 0) {
      y = x;
      lu.solve(y);
    }
    const double norm = y.lpNorm<1>();
    if (!std::isfinite(norm)) return INFINITY;
    if (iteration > 0 && norm <= estimate) break;
    estimate = norm;
    z = y.unaryExpr([](double v) { return v >= 0 ? 1.0 : -1.0; });
    lu.solve_transposed(z);
    Index j = 0;
    z.col(0).cwiseAbs().maxCoeff(&j);
    // x = e_previous_j here, so zᵀx = z(previous_j).
    if (iteration > 0 && (j == previous_j || std::abs(z(j)) <= z(previous_j))) break;
    previous_j = j;
    x.setZero();
    x(j) = 1.0;
  }
  return std::max(estimate, alternative);
}

void FactorizedSystem::apply_inverse(MatX& y) const {
  y.array().colwise() *= scaling_.row.array();
  solver_->solve(y);
  y.array().colwise() *= scaling_.column.array();
}

// The right-hand sides, kept once their dense storage has become the solution: a load or a
// unit wrench puts nonzeros in a few equations only.
class SparseColumns {
 public:
  explicit SparseColumns(const MatX& b) : columns_(b.sparseView(0.0, 0.0)) {}
  Index rows() const { return columns_.rows(); }
  double norm_inf(Index c) const {
    double largest = 0;
    for (SparseMatrix::InnerIterator e(columns_, c); e; ++e)
      largest = std::max(largest, std::abs(e.value()));
    return largest;
  }
  // f(row, value) for every nonzero of column c.
  template <class F>
  void for_each(Index c, F f) const {
    for (SparseMatrix::InnerIterator e(columns_, c); e; ++e) f(e.row(), e.value());
  }

 private:
  SparseMatrix columns_;
};

namespace {

// ‖r‖∞ / (‖A‖∞·‖x‖∞ + ‖b‖∞) from ‖r‖∞ (finite, ≥ 0).
template <class X>
double normwise(double residual_norm, double a_norm_inf, const X& x, double b_norm_inf) {
  return normwise_backward_error(residual_norm, a_norm_inf, x.template lpNorm<Eigen::Infinity>(),
                                 b_norm_inf);
}

// r = b − A·x accumulated in extended precision: refinement then converges to the solution as
// exactly as double can hold it, where a residual in double would stall at cond(A)·ε.
class ExtendedResidual {
 public:
  explicit ExtendedResidual(const SparseMatrix& a)
      : a_(a),
        sum_(static_cast<std::size_t>(a.rows())),
        magnitude_(static_cast<std::size_t>(a.rows())) {}

  // Of column c of b.
  template <class X, class R>
  BackwardError operator()(const X& x, const SparseColumns& b, Index c, double a_norm_inf, R&& r) {
    std::fill(sum_.begin(), sum_.end(), 0.0L);
    std::fill(magnitude_.begin(), magnitude_.end(), 0.0);
    b.for_each(c, [&](Index i, double v) {
      sum_[static_cast<std::size_t>(i)] = v;
      magnitude_[static_cast<std::size_t>(i)] = std::abs(v);
    });
    for (Index j = 0; j < a_.outerSize(); ++j) {
      const long double xj = x(j);
      if (xj == 0) continue;
      const double magnitude_j = std::abs(x(j));
      for (SparseMatrix::InnerIterator e(a_, j); e; ++e) {
        const auto i = static_cast<std::size_t>(e.row());
        sum_[i] -= static_cast<long double>(e.value()) * xj;
        magnitude_[i] += std::abs(e.value()) * magnitude_j;
      }
    }
    BackwardError error;
    double largest = 0;
    bool finite = true;
    for (Index i = 0; i < b.rows(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      r(i) = static_cast<double>(sum_[k]);
      const double size = std::abs(r(i));
      finite &= std::isfinite(size);
      largest = std::max(largest, size);
      if (size > 0)
        error.componentwise =
            std::max(error.componentwise, magnitude_[k] > 0 ? size / magnitude_[k] : INFINITY);
    }
    if (!finite) return {INFINITY, INFINITY};
    error.normwise = normwise(largest, a_norm_inf, x, b.norm_inf(c));
    return error;
  }

 private:
  const SparseMatrix& a_;
  std::vector<long double> sum_;
  std::vector<double> magnitude_;
};

// max_i |d_i| / |x_i| over the nonzero x_i.
template <class D, class X>
double largest_relative_change(const D& d, const X& x) {
  double largest = 0;
  for (Index i = 0; i < x.rows(); ++i)
    if (x(i) != 0) largest = std::max(largest, std::abs(d(i)) / std::abs(x(i)));
  return largest;
}
}  // namespace

namespace {
// B − A·X, every column in one pass over A, with X and the result stored by rows: an entry
// of A updates k adjacent sums from k adjacent values, where k sparse products, one per
// column, would each wait on their own read-modify-write chain.
// Columns first .. first + x.cols() − 1 of B − A·X.
RowMajorMatX residuals(const SparseMatrix& a, const Eigen::Ref<const MatX>& x,
                       const SparseColumns& b, Index first) {
  const RowMajorMatX x_rows = x;
  RowMajorMatX r = RowMajorMatX::Zero(x.rows(), x.cols());
  for (Index c = 0; c < r.cols(); ++c)
    b.for_each(first + c, [&](Index i, double v) { r(i, c) = v; });
  for (Index j = 0; j < a.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(a, j); e; ++e)
      r.row(e.row()).noalias() -= e.value() * x_rows.row(j);
  return r;
}

// Per column, ‖b − A·x‖∞ / (‖A‖∞·‖x‖∞ + ‖b‖∞) with the residual in double. The residuals of
// as many columns at once as fit in kResidualBlockEntries: all of a robot's, one at a time on
// a long chain (where n×k more doubles would raise the peak memory by 134 MB).
std::vector<double> normwise_backward_errors(const SparseMatrix& a, double a_norm_inf,
                                             const MatX& x, const SparseColumns& b) {
  constexpr Index kResidualBlockEntries = Index{1} << 20;
  const Index block = std::max<Index>(1, kResidualBlockEntries / std::max<Index>(1, x.rows()));
  std::vector<double> errors(static_cast<std::size_t>(x.cols()));
  for (Index first = 0; first < x.cols(); first += block) {
    const Index count = std::min(block, x.cols() - first);
    const RowMajorMatX r = residuals(a, x.middleCols(first, count), b, first);
    for (Index c = first; c < first + count; ++c) {
      const double numerator = r.col(c - first).lpNorm<Eigen::Infinity>();
      errors[static_cast<std::size_t>(c)] =
          std::isfinite(numerator) && x.col(c).allFinite()
              ? normwise(numerator, a_norm_inf, x.col(c), b.norm_inf(c))
              : INFINITY;
    }
  }
  return errors;
}
}  // namespace

double normwise_backward_error(double residual_norm, double a_norm_inf, double x_norm_inf,
                               double b_norm_inf) {
  if (residual_norm == 0) return 0.0;
  const double scale = a_norm_inf * x_norm_inf + b_norm_inf;
  return scale > 0 ? residual_norm / scale : INFINITY;
}

double relative_residual(const SparseMatrix& a, const MatX& x, const MatX& b) {
  const std::vector<double> errors = normwise_backward_errors(a, norm_inf(a), x, SparseColumns(b));
  return errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
}

MatX FactorizedSystem::solve(MatX b, int refinement_steps, double& residual) const {
  const SparseColumns rhs(b);
  MatX x = std::move(b);
  apply_inverse(x);
  const double condition = rcond_ > 0 ? 1.0 / rcond_ : INFINITY;
  const std::vector<double> normwise = normwise_backward_errors(*a_, a_norm_inf_, x, rhs);
  std::vector<BackwardError> error(normwise.size());
  // The columns share one factorisation: where one may have lost digits, all are refined.
  bool any = false;
  for (std::size_t k = 0; k < normwise.size(); ++k) {
    error[k].normwise = normwise[k];
    any |= normwise[k] * condition > kRefineAbove;
  }
  if (any && refinement_steps > 0) refine(rhs, refinement_steps, x, error);
  residual = 0;
  for (const BackwardError& e : error) residual = std::max(residual, e.normwise);
  return x;
}

void FactorizedSystem::refine(const SparseColumns& b, int steps, MatX& x,
                              std::vector<BackwardError>& error) const {
  // Column by column, each with its own n-vectors: the residual, solved in place into the
  // correction; the next residual; the column before the step, so that a step that makes it
  // worse can be taken back. (An n×k residual block would save little solve time and cost
  // 134 MB on a 100 000-link chain.)
  constexpr double epsilon = std::numeric_limits<double>::epsilon();
  ExtendedResidual residual_of(*a_);
  MatX correction(b.rows(), 1);
  VecX next(b.rows()), previous(b.rows());
  for (Index c = 0; c < x.cols(); ++c) {
    const auto k = static_cast<std::size_t>(c);
    error[k] = residual_of(x.col(c), b, c, a_norm_inf_, correction.col(0));
    for (int step = 0; step < steps && error[k].normwise > 0; ++step) {
      apply_inverse(correction);
      previous = x.col(c);
      x.col(c) += correction.col(0);
      const BackwardError candidate = residual_of(x.col(c), b, c, a_norm_inf_, next);
      // Near convergence the backward error is rounding and jitters; only a step that makes
      // it clearly worse is taken back.
      if (!(candidate.componentwise <= 2 * error[k].componentwise + epsilon)) {
        x.col(c) = previous;
        break;
      }
      error[k] = candidate;
      // Converged once the correction moves no unknown by more than a rounding of itself.
      if (largest_relative_change(correction.col(0), x.col(c)) <= epsilon) break;
      correction.col(0) = next;
    }
  }
}

}  // namespace stiffmsa::detail
