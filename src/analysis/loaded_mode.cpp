// The loaded mode: load steps of Newton iterations on the loaded blocks, then the tangent
// compliance at the equilibrium (docs/theory.md §15).
#include "analysis/loaded_mode.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "analysis/cartesian.hpp"
#include "elements/beam_element.hpp"
#include "elements/cad_link.hpp"
#include "elements/finite_rotation.hpp"
#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

namespace {

// Newton's iterations have converged where the step's correction, in the scaled norm of
// `correction_size`, is below this fraction of the state it corrects: the quadratic convergence
// puts the state's own error far below it.
constexpr double kNewtonTolerance = 1e-10;
// Where rounding stops the corrections from shrinking (they no longer fall by this factor), a
// correction below kNewtonFloor of the state is the equilibrium to working precision.
constexpr double kStagnationRatio = 0.25;
constexpr double kNewtonFloor = 1e-7;
// A correction below this (of the model size, or in radians) is at the rounding of the state
// itself, which holds positions and rotation matrices of size ~1: no iteration can do better.
constexpr double kRoundingFloor = 1e-13;
// The last iterate's tangent is the equilibrium's where the last correction is below this
// fraction of the state's motion, or where it is at the rounding of the state's own storage: a
// motion below kStateRounding of the model size (positions of size L and rotation matrices of
// size 1 hold no finer digit) and wrenches below kStateRounding of their scale.
constexpr double kTangentKept = 1e-13;
constexpr double kStateRounding = 1e-15;
// At most this many iterations in a load step before it is cut in half.
constexpr int kMostIterations = 30;
// A correction that turns a link end by more than this (rad) is no Newton step near an
// equilibrium: the step is cut.
constexpr double kLargestTurn = 1.0;
// The smallest load step tried before the path is declared to end (at the last equilibrium).
constexpr double kSmallestLoadStep = 1e-5;
// Where the path passes a critical point, the step is halved until the critical load factor is
// known to this width.
constexpr double kCriticalBracket = 1e-4;
// The tangent compliance's solve is refined where some column's normwise backward error
// exceeds this: a backward-stable factorisation leaves a few units of rounding, so more means
// digits were lost to pivot growth.
constexpr double kRefinedBackwardError = 1e-14;

std::string message_of(const std::ostringstream& text) { return text.str(); }

Vec3 position_of(const Model& model, const Topology& topology, int end) {
  return model.points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(end)])]
      .position;
}

// The scales a correction is measured in: lengths against the model size, wrenches against the
// largest force (and moment over the model size) of the loads and of the state.
struct Scales {
  double length = 1;
  double force = 1;
};

// max(|δx|/L, |δθ|) and max(|δF|, |δM|/L)/force over the link ends.
std::pair<double, double> correction_size(const Eigen::Ref<const VecX>& step,
                                          const Scales& scales) {
  double motion = 0, wrench = 0;
  for (Index e = 0; e < step.size() / 12; ++e) {
    const auto s = step.segment<12>(12 * e);
    motion = std::max({motion, s.segment<3>(0).cwiseAbs().maxCoeff() / scales.length,
                       s.segment<3>(3).cwiseAbs().maxCoeff()});
    wrench = std::max({wrench, s.segment<3>(6).cwiseAbs().maxCoeff(),
                       s.segment<3>(9).cwiseAbs().maxCoeff() / scales.length});
  }
  return {motion, wrench / scales.force};
}

// The same sizes of the state itself (its motion from the unloaded pose, its wrenches).
std::pair<double, double> state_size(const std::vector<EndState>& ends,
                                     const std::vector<Vec3>& unloaded, const Scales& scales) {
  double motion = 0, wrench = 0;
  for (std::size_t e = 0; e < ends.size(); ++e) {
    motion =
        std::max({motion, (ends[e].position - unloaded[e]).cwiseAbs().maxCoeff() / scales.length,
                  rotation_vector_of(ends[e].rotation).cwiseAbs().maxCoeff()});
    wrench = std::max({wrench, ends[e].wrench.head<3>().cwiseAbs().maxCoeff(),
                       ends[e].wrench.tail<3>().cwiseAbs().maxCoeff() / scales.length});
  }
  return {motion, wrench / scales.force};
}

void apply_correction(const Eigen::Ref<const VecX>& step, std::vector<EndState>& ends) {
  for (std::size_t e = 0; e < ends.size(); ++e) {
    const auto s = step.segment<12>(12 * static_cast<Index>(e));
    ends[e].position += s.segment<3>(0);
    ends[e].rotation = rotation_matrix(s.segment<3>(3)) * ends[e].rotation;
    ends[e].wrench += s.segment<6>(6);
  }
}

struct Path {
  const std::vector<std::unique_ptr<LoadedBlock>>& blocks;
  LoadedTangent& tangent;
  std::vector<Vec6> full_external;  // per link end, at λ = 1
  std::vector<Vec3> unloaded;
  // The linear solution of the full loads (with the preloads and settlements) per link end, as
  // a state: the start of the path's first step, times its load factor. Empty where the linear
  // result lacks a link end's deflection or wrench.
  std::vector<Vec6> linear_deflection, linear_wrench;
  Scales scales;
  int iterations = 0;
  int load_steps = 0;
  // Whether the last converged step's last correction was at rounding level, so that the
  // tangent factorised for it is the equilibrium's to as many digits.
  bool tangent_at_equilibrium = false;

  std::vector<Vec6> external_at(double factor) const {
    std::vector<Vec6> w(full_external.size());
    for (std::size_t e = 0; e < w.size(); ++e) w[e] = factor * full_external[e];
    return w;
  }

  // The state λ·linear (rotations exp(λ·φ)) in `ends`: the linear solution of the loads λ·W,
  // where Newton's first step from the unloaded pose would land but for the terms of the
  // tangent proportional to the loads. False (`ends` unchanged) where it turns some link end by
  // more than kLargestTurn, as that first step would have been refused.
  bool start_from_linear(double factor, std::vector<EndState>& ends) const {
    double motion = 0;
    for (const Vec6& t : linear_deflection)
      motion = std::max({motion, factor * t.head<3>().cwiseAbs().maxCoeff() / scales.length,
                         factor * t.tail<3>().cwiseAbs().maxCoeff()});
    if (motion > kLargestTurn) return false;
    for (std::size_t e = 0; e < ends.size(); ++e) {
      ends[e].position = unloaded[e] + factor * linear_deflection[e].head<3>();
      ends[e].rotation = rotation_matrix(Vec3(factor * linear_deflection[e].tail<3>()));
      ends[e].wrench = factor * linear_wrench[e];
    }
    return true;
  }

  // Newton's iterations at load factor `factor` from `ends`; true with `ends` in equilibrium and
  // the tangent factorised at the last iterate, false (ends unspecified) where they do not
  // converge.
  bool equilibrium(double factor, std::vector<EndState>& ends) {
    const std::vector<Vec6> external = external_at(factor);
    VecX residual;
    MatX correction;
    double last_motion = std::numeric_limits<double>::infinity();
    for (int iteration = 0; iteration < kMostIterations; ++iteration) {
      ++iterations;
      const LoadedInputs in{ends, external, factor};
      if (!tangent.evaluate(in, residual, true)) return false;
      correction = -residual;
      tangent.solve(correction);
      const auto step = correction.col(0);
      if (!step.allFinite()) return false;
      const auto [motion, wrench] = correction_size(step, scales);
      apply_correction(step, ends);
      const auto [state_motion, state_wrench] = state_size(ends, unloaded, scales);
      if (motion > kLargestTurn) return false;
      const bool small = motion <= kNewtonTolerance * state_motion &&
                         wrench <= kNewtonTolerance * std::max(state_wrench, 1.0);
      const bool stalled = motion > kStagnationRatio * last_motion &&
                           motion <= kNewtonFloor * state_motion &&
                           wrench <= kNewtonFloor * std::max(state_wrench, 1.0);
      const bool rounding =
          motion <= kRoundingFloor && wrench <= kNewtonFloor * std::max(state_wrench, 1.0);
      if (small || stalled || rounding) {
        // The joints' and supports' tangents depend on the wrenches too: both must be settled.
        tangent_at_equilibrium =
            (motion <= kTangentKept * state_motion &&
             wrench <= kTangentKept * std::max(state_wrench, 1.0)) ||
            (motion <= kStateRounding && wrench <= kStateRounding * std::max(state_wrench, 1.0));
        return true;
      }
      last_motion = motion;
    }
    return false;
  }
};

std::string factor_text(double f) {
  std::ostringstream text;
  text.precision(6);
  text << f;
  return text.str();
}

}  // namespace

std::vector<std::unique_ptr<LoadedBlock>> make_loaded_blocks(
    const Model& model, const Topology& topology,
    const std::vector<std::vector<LoadAlongLink>>& along) {
  std::vector<std::unique_ptr<LoadedBlock>> blocks;
  for (int l = 0; l < topology.link_count; ++l) {
    const Link& link = model.links[static_cast<std::size_t>(l)];
    const int from = 2 * l, to = 2 * l + 1;
    const Vec3 p_from = position_of(model, topology, from), p_to = position_of(model, topology, to);
    const Vec3 d = p_to - p_from;
    if (std::holds_alternative<RigidLink>(link.kind)) {
      blocks.push_back(
          with_loads_along(make_loaded_rigid_link(from, to, d), link, p_from, p_to, along[l]));
      continue;
    }
    CorotationalLink element;
    element.d0 = d;
    if (const auto* beam = std::get_if<BeamLink>(&link.kind)) {
      element.stiffness = beam_global_stiffness(*beam, p_from, p_to);
      element.axial = beam->material.E * section_properties(beam->section).A;
    } else if (const auto* matrix = std::get_if<MatrixLink>(&link.kind)) {
      element.stiffness = matrix_link_global_stiffness(*matrix, p_from, p_to);
    } else {
      element.stiffness = free_free_stiffness(
          compliance_link_global_compliance(std::get<ComplianceLink>(link.kind), p_from, p_to), d);
    }
    blocks.push_back(
        with_loads_along(make_corotational_link(from, to, element), link, p_from, p_to, along[l]));
  }
  FreeDirections locked;  // no free direction: a weld, a locked drive
  for (const ConnectionGroup& g : topology.groups) {
    switch (g.kind) {
      case ConnectionGroup::Kind::free_end:
        blocks.push_back(make_loaded_free_end(g.ends.front()));
        break;
      case ConnectionGroup::Kind::rigid_connection:
        blocks.push_back(make_loaded_constraint_joint(g.ends, locked, std::nullopt));
        break;
      case ConnectionGroup::Kind::joint: {
        const Connection& c = model.joints[static_cast<std::size_t>(g.source)].connection;
        if (c.stiffness)
          blocks.push_back(make_loaded_elastic_joint(
              g.ends[0], g.ends[1], free_directions(c.kinematics), *c.stiffness, c.preload));
        else if (c.is_actuated)
          blocks.push_back(make_loaded_constraint_joint(g.ends, locked, std::nullopt));
        else
          blocks.push_back(
              make_loaded_constraint_joint(g.ends, free_directions(c.kinematics), c.preload));
        break;
      }
      case ConnectionGroup::Kind::support: {
        const Support& s = model.supports[static_cast<std::size_t>(g.source)];
        const Connection& c = s.connection;
        const Vec3 at = position_of(model, topology, g.ends.front());
        if (c.is_actuated && !c.stiffness)
          blocks.push_back(
              make_loaded_support(g.ends, locked, std::nullopt, std::nullopt, s.displacement, at));
        else
          blocks.push_back(make_loaded_support(g.ends, free_directions(c.kinematics), c.stiffness,
                                               c.preload, s.displacement, at));
        break;
      }
    }
  }
  return blocks;
}

void LoadedTangent::begin(const std::vector<std::unique_ptr<LoadedBlock>>& blocks, Index unknowns) {
  blocks_ = &blocks;
  std::vector<int> layout;
  layout.reserve(layout_.size());
  layout.push_back(static_cast<int>(unknowns));
  for (const auto& b : blocks) {
    layout.push_back(static_cast<int>(b->equation_count()));
    layout.push_back(static_cast<int>(b->ends().size()));
    // Blocks of one pattern in each place keep the last pose's tangents, zero where they write
    // nothing (LoadedBlock::evaluate).
    layout.push_back(b->pattern());
    layout.insert(layout.end(), b->ends().begin(), b->ends().end());
  }
  if (layout != layout_) {
    // The layout is kept only once it is analysed, so that a failed analysis is done again at
    // the next pose instead of leaving analyses of another layout.
    layout_.clear();
    n_ = unknowns;
    first_row_.clear();
    tangents_.assign(blocks.size(), MatX());
    BlockLayout block_layout;
    block_layout.group_count = static_cast<int>(unknowns / kBlockColumns);
    Index row = 0;
    for (const auto& b : blocks) {
      first_row_.push_back(row);
      row += b->equation_count();
      block_layout.rows.push_back(static_cast<int>(b->equation_count()));
      block_layout.groups.push_back(b->ends());
    }
    positions_.clear();
    solver_.reset();
    unloaded_solver_.reset();
    unloaded_scaling_.reset();
    unloaded_reference_ = false;
    if (uses_block_lu())
      block_lu_.analyze(block_layout);
    else
      record_pattern();
    layout_ = std::move(layout);
  }
  if (solver_) solver_->renew_reference();
  scaling_.reset();
  newton_by_block_lu_ = false;
  newton_factorised_ = false;
}

void LoadedTangent::record_pattern() {
  if (!positions_.empty()) return;
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t b = 0; b < blocks_->size(); ++b) {
    const LoadedBlock& block = *(*blocks_)[b];
    const Index rows = block.equation_count(), row = first_row_[b];
    const auto& ends = block.ends();
    for (std::size_t k = 0; k < ends.size(); ++k)
      for (Index c = 0; c < 12; ++c)
        for (Index i = 0; i < rows; ++i)
          entries.emplace_back(static_cast<int>(row + i), static_cast<int>(12 * ends[k] + c), 1.0);
  }
  matrix_.resize(n_, n_);
  matrix_.setFromTriplets(entries.begin(), entries.end());
  matrix_.makeCompressed();
  std::vector<int> positions;
  positions.reserve(entries.size());
  for (const auto& e : entries) {
    const int* first = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[e.col()];
    const int* last = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[e.col() + 1];
    positions.push_back(
        static_cast<int>(std::lower_bound(first, last, e.row()) - matrix_.innerIndexPtr()));
  }
  scaled_ = matrix_;
  solver_ = make_linear_solver(kind_);
  solver_->analyze(scaled_);
  unloaded_solver_ = make_linear_solver(kind_);
  unloaded_solver_->analyze(scaled_);
  unloaded_scaling_.reset();
  positions_ = std::move(positions);
}

void LoadedTangent::assemble(const LoadedInputs& in, VecX& residual, bool with_tangent) {
  residual.resize(n_);
  for (std::size_t b = 0; b < blocks_->size(); ++b) {
    const LoadedBlock& block = *(*blocks_)[b];
    block.evaluate(in, residual.segment(first_row_[b], block.equation_count()),
                   with_tangent ? &tangents_[b] : nullptr);
  }
}

void LoadedTangent::scatter() {
  record_pattern();
  double* const values = matrix_.valuePtr();
  std::fill(values, values + matrix_.nonZeros(), 0.0);
  const int* position = positions_.data();
  for (const MatX& tangent : tangents_) {
    const double* entry = tangent.data();
    for (Index k = 0; k < tangent.size(); ++k) values[position[k]] += entry[k];
    position += tangent.size();
  }
}

void LoadedTangent::scale(const Equilibration& scaling) {
  const double* const values = matrix_.valuePtr();
  double* const scaled = scaled_.valuePtr();
  const int* const rows = matrix_.innerIndexPtr();
  for (Index j = 0; j < n_; ++j) {
    const double column = scaling.column(j);
    for (int k = matrix_.outerIndexPtr()[j]; k < matrix_.outerIndexPtr()[j + 1]; ++k)
      scaled[k] = values[k] * scaling.row(rows[k]) * column;
  }
}

bool LoadedTangent::evaluate(const LoadedInputs& in, VecX& residual, bool factorise) {
  assemble(in, residual, factorise);
  if (!factorise) return true;
  // Every Newton tangent is scaled afresh: a kept scaling would change the pivots, and so the
  // results' rounding, wherever a row's largest entry crosses a power of two between them.
  newton_by_block_lu_ =
      uses_block_lu() && block_lu_.factorise(tangents_) == BlockLU::Outcome::factorised;
  newton_factorised_ = newton_by_block_lu_;
  if (newton_by_block_lu_) return true;
  // The tangents of a case's Newton iterations differ little: the first one's scaling serves
  // them all, as its pivot order does.
  scatter();
  if (!scaling_) scaling_ = equilibrate(matrix_);
  scale(*scaling_);
  newton_factorised_ = solver_->factorize(scaled_);
  return newton_factorised_;
}

double LoadedTangent::unloaded_determinant_sign(const LoadedInputs& in) {
  VecX residual;
  assemble(in, residual, true);
  // The block LU's factors are the Newton tangent's from here on no more: the next evaluate
  // factorises again before any solve.
  newton_by_block_lu_ = false;
  newton_factorised_ = false;
  if (uses_block_lu()) {
    // The sign does not depend on the scaling (nor on the pivots): the last pose's unloaded
    // scaling serves, afresh where it does not factorise. Only a tangent whose smallest pivot
    // is near kBlockLuTinyPivot may then take the other path than a fresh scaling would send
    // it to (as the sparse path's kept pivots already made its outcome there depend on the
    // last pose): theory §15.10.
    using Outcome = BlockLU::Outcome;
    Outcome outcome = Outcome::singular;
    if (unloaded_reference_) outcome = block_lu_.factorise(tangents_, &unloaded_block_scaling_);
    if (outcome != Outcome::factorised) {
      outcome = block_lu_.factorise(tangents_);
      unloaded_reference_ = outcome == Outcome::factorised;
      if (unloaded_reference_) unloaded_block_scaling_ = block_lu_.scaling();
    }
    if (outcome == Outcome::factorised) return block_lu_.determinant_sign();
  }
  scatter();
  unloaded_scaling_ = equilibrate(matrix_, unloaded_scaling_ ? &*unloaded_scaling_ : nullptr);
  scale(*unloaded_scaling_);
  if (!unloaded_solver_->factorize(scaled_)) return 0.0;
  // The next pose's unloaded tangent is likelier to suit this one's pivots than an older one's
  // (a sweep's neighbouring poses); which pivots give the sign does not matter.
  unloaded_solver_->adopt_last_as_reference();
  return unloaded_solver_->determinant_sign();
}

void LoadedTangent::solve(MatX& b) const {
  if (newton_by_block_lu_) {
    block_lu_.solve(b);
    return;
  }
  b.array().colwise() *= scaling_->row.array();
  solver_->solve(b);
  b.array().colwise() *= scaling_->column.array();
}

namespace {

// sum[i] += Σ_j |t(i, j)| over a block's tangent of `Rows` rows (0: t.rows() at run time).
template <int Rows>
void add_row_sizes(const MatX& t, double* __restrict sum) {
  const Index rows = Rows > 0 ? Rows : t.rows();
  const double* entry = t.data();
  for (Index j = 0; j < t.cols(); ++j, entry += rows)
    for (Index i = 0; i < rows; ++i) sum[i] += std::abs(entry[i]);
}

}  // namespace

double LoadedTangent::norm_inf() const {
  VecX row_sum = VecX::Zero(n_);
  for (std::size_t k = 0; k < tangents_.size(); ++k) {
    const MatX& t = tangents_[k];
    double* const sum = row_sum.data() + first_row_[k];
    std::fill(sum, sum + t.rows(), 0.0);
    switch (t.rows()) {
      case 12: add_row_sizes<12>(t, sum); break;
      case 6: add_row_sizes<6>(t, sum); break;
      default: add_row_sizes<0>(t, sum);
    }
  }
  return n_ > 0 ? row_sum.maxCoeff() : 0.0;
}

namespace {

// residual −= T·x over one block's rows: T (`Rows` × 12 per end, column-major, as the block
// writes its tangent) times x's rows of each end, two columns of x at a time (each entry of T
// read once for both), the block's rows of the residual held in local arrays; each column's
// sums in the same order as alone. Fixed row counts (a link's or a two-end joint's 12, a
// one-end connection's 6) unroll the rows.
template <int Rows>
void subtract_block_product(const MatX& t, const std::vector<int>& ends, const MatX& x,
                            Index first_row, MatX& residual) {
  Index c = 0;
  for (; c + 1 < x.cols(); c += 2) {
    double* const r0 = residual.col(c).data() + first_row;
    double* const r1 = residual.col(c + 1).data() + first_row;
    std::array<double, Rows> sum0, sum1;
    std::copy_n(r0, Rows, sum0.begin());
    std::copy_n(r1, Rows, sum1.begin());
    const double* entry = t.data();
    for (int end : ends) {
      const double* const u0 = x.col(c).data() + 12 * static_cast<Index>(end);
      const double* const u1 = x.col(c + 1).data() + 12 * static_cast<Index>(end);
      for (int p = 0; p < 12; ++p, entry += Rows)
        for (int i = 0; i < Rows; ++i) {
          sum0[i] -= entry[i] * u0[p];
          sum1[i] -= entry[i] * u1[p];
        }
    }
    std::copy_n(sum0.begin(), Rows, r0);
    std::copy_n(sum1.begin(), Rows, r1);
  }
  for (; c < x.cols(); ++c) {
    double* const r = residual.col(c).data() + first_row;
    std::array<double, Rows> sum;
    std::copy_n(r, Rows, sum.begin());
    const double* entry = t.data();
    for (int end : ends) {
      const double* const unknowns = x.col(c).data() + 12 * static_cast<Index>(end);
      for (int p = 0; p < 12; ++p, entry += Rows)
        for (int i = 0; i < Rows; ++i) sum[i] -= entry[i] * unknowns[p];
    }
    std::copy_n(sum.begin(), Rows, r);
  }
}

// The same for any row count.
void subtract_block_product_any(const MatX& t, const std::vector<int>& ends, const MatX& x,
                                Index first_row, MatX& residual) {
  const Index rows = t.rows();
  for (Index c = 0; c < x.cols(); ++c) {
    double* const r = residual.col(c).data() + first_row;
    const double* entry = t.data();
    for (int end : ends) {
      const double* const unknowns = x.col(c).data() + 12 * static_cast<Index>(end);
      for (int p = 0; p < 12; ++p, entry += rows)
        for (Index i = 0; i < rows; ++i) r[i] -= entry[i] * unknowns[p];
    }
  }
}

}  // namespace

double LoadedTangent::backward_error(const MatX& b, const MatX& x, double a_norm,
                                     MatX& residual) const {
  residual = b;
  for (std::size_t k = 0; k < tangents_.size(); ++k) {
    const MatX& t = tangents_[k];
    const auto& ends = (*blocks_)[k]->ends();
    switch (t.rows()) {
      case 12: subtract_block_product<12>(t, ends, x, first_row_[k], residual); break;
      case 6: subtract_block_product<6>(t, ends, x, first_row_[k], residual); break;
      default: subtract_block_product_any(t, ends, x, first_row_[k], residual);
    }
  }
  double largest = 0;
  for (Index c = 0; c < b.cols(); ++c)
    largest = std::max(largest, normwise_backward_error(residual.col(c).cwiseAbs().maxCoeff(),
                                                        a_norm, x.col(c).cwiseAbs().maxCoeff(),
                                                        b.col(c).cwiseAbs().maxCoeff()));
  return largest;
}

MatX LoadedTangent::solve_checked(const MatX& b, int refinement_steps,
                                  double& relative_residual) const {
  MatX x = b, residual;
  solve(x);
  const double a_norm = norm_inf();
  relative_residual = backward_error(b, x, a_norm, residual);
  for (int step = 0; step < refinement_steps && relative_residual > kRefinedBackwardError; ++step) {
    solve(residual);
    const MatX refined = x + residual;
    MatX next_residual;
    const double refined_error = backward_error(b, refined, a_norm, next_residual);
    if (!(refined_error < relative_residual)) break;
    x = refined;
    residual = std::move(next_residual);
    relative_residual = refined_error;
  }
  return x;
}

double LoadedTangent::determinant_sign() const {
  if (!newton_factorised_)
    throw UsageError(
        "the loaded tangent's determinant sign was asked for before a Newton tangent was "
        "factorised (LoadedTangent::evaluate with factorisation)");
  return newton_by_block_lu_ ? block_lu_.determinant_sign() : solver_->determinant_sign();
}

const char* LoadedTangent::solver_name() const {
  return newton_by_block_lu_ ? "block_lu" : solver_->name();
}

std::vector<Vec6> end_loads(const Model& model, const Topology& topology) {
  std::vector<Vec6> loads(static_cast<std::size_t>(topology.end_count()), Vec6::Zero());
  for (std::size_t i = 0; i < model.loads.size(); ++i)
    loads[static_cast<std::size_t>(topology.load_ends[i])] += model.loads[i].wrench;
  return loads;
}

Result loaded_result(const Model& model, const Topology& topology, const SolveOptions& options,
                     const Result& linear, const std::vector<Vec6>& loads, int load_steps,
                     LoadedTangent& tangent, const std::vector<ResolvedLinkLoad>& link_loads) {
  std::vector<std::vector<LoadAlongLink>> along(model.links.size());
  for (const ResolvedLinkLoad& l : link_loads)
    along[static_cast<std::size_t>(l.link)].push_back(l.load);
  const std::vector<std::unique_ptr<LoadedBlock>> blocks =
      make_loaded_blocks(model, topology, along);
  const int end_count = topology.end_count();
  tangent.begin(blocks, topology.unknowns());
  // The tangent holds `blocks` by reference: it lets go of them however this function ends.
  struct Release {
    LoadedTangent& tangent;
    ~Release() { tangent.end(); }
  } release{tangent};
  Path path{blocks, tangent, loads, {}, {}, {}, {}, 0, 0};
  path.scales.length = characteristic_length(model);
  double force = 0;
  for (const Vec6& w : path.full_external)
    force = std::max({force, w.head<3>().cwiseAbs().maxCoeff(),
                      w.tail<3>().cwiseAbs().maxCoeff() / path.scales.length});
  for (const LinkResult& l : linear.links)
    for (const LinkEndResult* end : {&l.from, &l.to})
      if (end->wrench)
        force = std::max({force, end->wrench->head<3>().cwiseAbs().maxCoeff(),
                          end->wrench->tail<3>().cwiseAbs().maxCoeff() / path.scales.length});
  path.scales.force = force > 0 ? force : 1.0;
  for (const LinkResult& l : linear.links)
    for (const LinkEndResult* end : {&l.from, &l.to})
      if (end->deflection && end->wrench) {
        path.linear_deflection.push_back(*end->deflection);
        path.linear_wrench.push_back(*end->wrench);
      }
  if (path.linear_deflection.size() != static_cast<std::size_t>(topology.end_count())) {
    path.linear_deflection.clear();
    path.linear_wrench.clear();
  }

  std::vector<EndState> ends(static_cast<std::size_t>(end_count));
  for (int e = 0; e < end_count; ++e) {
    ends[static_cast<std::size_t>(e)].position = position_of(model, topology, e);
    path.unloaded.push_back(ends[static_cast<std::size_t>(e)].position);
  }

  // The tangent's determinant keeps its sign along the path until it passes a critical point.
  VecX residual;
  const std::vector<Vec6> none(static_cast<std::size_t>(end_count), Vec6::Zero());
  const double unloaded_sign =
      path.tangent.unloaded_determinant_sign(LoadedInputs{ends, none, 0.0});
  if (unloaded_sign == 0)
    throw SingularModelError(SingularModelError::Cause::numerical,
                             "the loaded mode needs a regular tangent at the unloaded pose, and "
                             "this model's is singular (a mechanism, or idle motions that the "
                             "linear mode accepted)",
                             {});

  const double nominal = 1.0 / std::max(load_steps, 1);
  double reached = 0, step = nominal;
  while (reached < 1.0) {
    const double target = std::min(1.0, reached + step);
    std::vector<EndState> trial = ends;
    // The first step starts from the linear solution of its loads.
    const bool from_linear = reached == 0 && !path.linear_deflection.empty();
    const bool converged =
        (!from_linear || path.start_from_linear(target, trial)) && path.equilibrium(target, trial);
    const bool critical = converged && path.tangent.determinant_sign() != unloaded_sign;
    if (converged && !critical) {
      ends = std::move(trial);
      reached = target;
      ++path.load_steps;
      step = std::min(nominal, 2 * step);
      continue;
    }
    if (critical && step < kCriticalBracket) {
      std::ostringstream text;
      text << "the loaded mode passed a critical point (a limit point or a bifurcation: the "
              "tangent stiffness turned singular) between load factors "
           << factor_text(reached) << " and " << factor_text(target)
           << " of the loads; the structure buckles or snaps there";
      throw NoEquilibriumError(message_of(text), reached);
    }
    if (!critical && step < kSmallestLoadStep) {
      std::ostringstream text;
      text << "the loaded mode found no equilibrium beyond load factor " << factor_text(reached)
           << " of the loads: Newton's iterations do not converge however small the load step "
              "(a limit point, where the structure snaps or collapses, or loads beyond what it "
              "can carry)";
      throw NoEquilibriumError(message_of(text), reached);
    }
    step /= 2;
  }

  // The tangent at the equilibrium itself, and its response to a unit wrench at each end
  // effector: J·δ = r(W_ext) − r(W_ext + e_c) (the residual is linear in the external wrenches).
  const std::vector<Vec6> external = path.external_at(1.0);
  const LoadedInputs at_equilibrium{ends, external, 1.0};
  // Formed again unless the last correction was at rounding level (the tangent then differs
  // from the equilibrium's by as little).
  if (!path.tangent_at_equilibrium && !path.tangent.evaluate(at_equilibrium, residual, true))
    throw NoEquilibriumError(
        "the loaded mode's tangent is singular at the equilibrium under the full loads: the "
        "structure is at a critical point there",
        1.0);

  Result result = linear;
  result.linear = std::make_shared<const Result>(linear);
  result.analysis = {AnalysisMode::loaded, path.load_steps, path.iterations};
  result.report.solver =
      solver_used_from_string(tangent.solver_name()).value_or(SolverUsed::sparse_lu);
  result.report.reciprocal_condition = 0;
  // The linear method's range no longer applies.
  std::erase_if(result.report.warnings, [&](const std::string& w) {
    return !result.report.large_deflection.empty() && w == result.report.large_deflection;
  });
  result.report.large_deflection.clear();

  auto deflection_of = [&](int e) {
    Vec6 t;
    t.head<3>() =
        ends[static_cast<std::size_t>(e)].position - path.unloaded[static_cast<std::size_t>(e)];
    t.tail<3>() = rotation_vector_of(ends[static_cast<std::size_t>(e)].rotation);
    return t;
  };
  for (int l = 0; l < topology.link_count; ++l) {
    LinkResult& r = result.links[static_cast<std::size_t>(l)];
    r.from = {deflection_of(2 * l), ends[static_cast<std::size_t>(2 * l)].wrench};
    r.to = {deflection_of(2 * l + 1), ends[static_cast<std::size_t>(2 * l + 1)].wrench};
  }
  for (const ConnectionGroup& g : topology.groups) {
    const EndState& first = ends[static_cast<std::size_t>(g.ends.front())];
    if (g.kind == ConnectionGroup::Kind::joint) {
      const Joint& joint = model.joints[static_cast<std::size_t>(g.source)];
      const FreeDirections directions = free_directions(joint.connection.kinematics);
      JointResult& r = result.joints[static_cast<std::size_t>(g.source)];
      std::vector<VecX> q;
      for (std::size_t k = 1; k < g.ends.size(); ++k) {
        const EndState& other = ends[static_cast<std::size_t>(g.ends[k])];
        Vec6 motion;
        motion.head<3>() = first.rotation.transpose() * (other.position - first.position);
        motion.tail<3>() = rotation_vector_of(first.rotation.transpose() * other.rotation);
        q.push_back(directions.free() * motion);
      }
      r.relative_deflection = std::move(q);
      const Vec6 wrench = first.wrench - external[static_cast<std::size_t>(g.ends.front())];
      r.wrench = wrench;
      if (joint.connection.is_actuated) {
        Vec6 in_axes;
        in_axes.head<3>() = first.rotation.transpose() * wrench.head<3>();
        in_axes.tail<3>() = first.rotation.transpose() * wrench.tail<3>();
        r.effort = VecX(directions.gram().ldlt().solve(directions.free() * in_axes));
      }
    } else if (g.kind == ConnectionGroup::Kind::support) {
      Vec6 reaction = Vec6::Zero();
      for (int end : g.ends) {
        const EndState& s = ends[static_cast<std::size_t>(end)];
        const Vec6 w = s.wrench - external[static_cast<std::size_t>(end)];
        reaction.head<3>() += w.head<3>();
        reaction.tail<3>() += w.tail<3>() + (s.position - first.position).cross(w.head<3>());
      }
      result.supports[static_cast<std::size_t>(g.source)].reaction = reaction;
    }
  }

  const double length = path.scales.length;
  double compliance_residual = 0;
  for (std::size_t e = 0; e < model.end_effectors.size(); ++e) {
    const int end = topology.effector_ends[e];
    const std::size_t holder = static_cast<std::size_t>(
        topology.link_count + topology.group_of_end[static_cast<std::size_t>(end)]);
    const LoadedBlock& block = *blocks[holder];
    const Index rows = block.equation_count(), first_row = path.tangent.first_row(holder);
    VecX base(rows), moved(rows);
    block.evaluate(at_equilibrium, base, nullptr);
    MatX rhs = MatX::Zero(topology.unknowns(), 6);
    for (int c = 0; c < 6; ++c) {
      std::vector<Vec6> pushed = external;
      pushed[static_cast<std::size_t>(end)] += Vec6::Unit(c);
      block.evaluate(LoadedInputs{ends, pushed, 1.0}, moved, nullptr);
      rhs.col(c).segment(first_row, rows) = base - moved;
    }
    double residual_of_solve = 0;
    const MatX x = path.tangent.solve_checked(rhs, options.refinement_steps, residual_of_solve);
    // A non-finite residual is a failed check, not one that std::max would drop.
    compliance_residual = std::isfinite(residual_of_solve)
                              ? std::max(compliance_residual, residual_of_solve)
                              : std::numeric_limits<double>::infinity();
    EndEffectorResult& r = result.end_effectors[e];
    const Mat6 compliance = x.middleRows<6>(12 * static_cast<Index>(end));
    r.compliance = compliance;
    r.deflection = deflection_of(end);
    r.reduced_stiffness.reset();
    r.along_direction.reset();
    r.in_own_axes.reset();
    const CartesianStiffness cartesian =
        cartesian_stiffness(compliance, length, options.warn_condition);
    r.stiffness = cartesian.stiffness;
    if (r.stiffness) {
      Mat6 weighted = *r.stiffness;  // rotations weighted by the model size, as in C's checks
      weighted.topRightCorner<3, 3>() *= length;
      weighted.bottomLeftCorner<3, 3>() *= length;
      weighted.bottomRightCorner<3, 3>() *= length * length;
      const double sum = (weighted + weighted.transpose()).norm();
      r.stiffness_asymmetry = sum > 0 ? (weighted - weighted.transpose()).norm() / sum : 0.0;
    } else {
      r.reduced_stiffness = reduced_stiffness(compliance, length);
    }
  }
  result.report.relative_residual = std::max(result.report.relative_residual, compliance_residual);
  if (compliance_residual > options.max_relative_residual) {
    std::ostringstream text;
    text << "the relative residual " << compliance_residual
         << " of the tangent compliance's solve exceeds " << options.max_relative_residual
         << "; results may be inaccurate";
    result.report.failed_checks.push_back(text.str());
    result.report.warnings.push_back(text.str());
  }
  return result;
}

}  // namespace stiffmsa::detail
