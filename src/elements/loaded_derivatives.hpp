#pragma once
// How a loaded block gets its tangent: written out from the pieces of this file
// (docs/theory.md §15.1).
#include <utility>

#include "elements/finite_rotation.hpp"
#include "elements/loaded_blocks.hpp"

namespace stiffmsa::detail {

template <class T>
using VecXT = Eigen::Matrix<T, Eigen::Dynamic, 1>;

// ---- Nested forward duals: the derivative of a gradient -----------------------------------
//
// For rows that are a gradient (the work of loads along a link, §15.9): inner variables a are
// the virtual motion whose work defines the gradient, outer ones b the Newton increment, 12 of
// each (two link ends' [δx; δθ]).
using NestedInner = Eigen::AutoDiffScalar<Eigen::Matrix<double, 12, 1>>;
using NestedDual = Eigen::AutoDiffScalar<Eigen::Matrix<NestedInner, 12, 1>>;

// A scalar of value v whose inner derivative `inner` and outer derivative `outer` are 1 (−1:
// none).
inline NestedDual nested_seeded(double v, int inner, int outer) {
  using Vec12d = Eigen::Matrix<double, 12, 1>;
  NestedInner value(v, Vec12d::Zero());
  if (inner >= 0) value.derivatives()(inner) = 1;
  Eigen::Matrix<NestedInner, 12, 1> derivatives;
  for (int k = 0; k < 12; ++k) derivatives(k) = NestedInner(0.0, Vec12d::Zero());
  if (outer >= 0) derivatives(outer) = NestedInner(1.0, Vec12d::Zero());
  return NestedDual(value, derivatives);
}

// An end's pose moved by increments a and b, its variables from `first`: x + a_x + b_x and
// (I + [a_θ×])·(I + [b_θ×])·R, the multiplicative update of §15.1 in both sets.
inline void nested_moved_pose(const EndState& s, int first, Vec3T<NestedDual>& x,
                              Mat3T<NestedDual>& rotation) {
  Vec3T<NestedDual> a, b;
  for (int i = 0; i < 3; ++i) {
    x(i) = nested_seeded(s.position(i), first + i, first + i);
    a(i) = nested_seeded(0, first + 3 + i, -1);
    b(i) = nested_seeded(0, -1, first + 3 + i);
  }
  const Mat3T<NestedDual> start = s.rotation.cast<NestedDual>();
  const Mat3T<NestedDual> after_b = start + skew_of(b) * start;
  rotation = after_b + skew_of(a) * after_b;
}

// ---- Closed-form rows and derivatives of the connection blocks and rigid links ----------------
//
// A block's tangent (rows × 12·ends, 12 columns per end: δx, δθ, δW) is written piece by piece:
// each piece below is a 3- or 6-vector of the rows' ingredients with its derivatives in the
// increments of the ends it involves, and `add_derivative` adds a projection of one of them
// into the tangent. Rotations turn as R ← (I + [δθ×])·R, so R's transpose turns as
// Rᵀ ← Rᵀ·(I − [δθ×]) and Rᵀ·v changes by Rᵀ·[v×]·δθ.

using Mat63 = Eigen::Matrix<double, 6, 3>;

// Rows [first, first + count) of a 6×6 matrix, times `sign`: a joint's Λ_p (rows 0…p of
// FreeDirections::rows) or Λ_r (rows p…6), a spring G·K·Λ_p padded with zero rows to 6. Products
// with it are taken at the fixed size 6, which the compiler unrolls, and its rows kept after.
struct SixRows {
  const Mat6& matrix;
  Index first = 0;
  Index count = 6;
  double sign = 1;
};
inline const Mat6 kSixIdentity = Mat6::Identity();

// A joint's or support's preload w0 as its free directions' rows meet it, G·w0; none without.
inline std::optional<SmallVec> held_preload(const FreeDirections& directions,
                                            const std::optional<VecX>& preload) {
  if (!preload) return std::nullopt;
  return SmallVec(directions.gram() * *preload);
}

// A joint's or support's spring G·K·Λ_p (p×6) in the top rows of a 6×6 matrix.
inline Mat6 padded_spring(const FreeDirections& directions, const MatX& stiffness) {
  Mat6 spring = Mat6::Zero();
  spring.topRows(directions.p) =
      SmallMat(directions.gram() * SmallMat(stiffness)) * directions.free();
  return spring;
}

// Adds rows·derivative into the tangent at `row`, columns `column` onwards.
template <class Derivative>
void add_derivative(MatX& tangent, Index row, Index column, const SixRows& rows,
                    const Derivative& derivative) {
  constexpr int kCols = Derivative::ColsAtCompileTime;
  if (&rows.matrix == &kSixIdentity && rows.count == 6) {  // no product, all six rows
    tangent.block<6, kCols>(row, column) += rows.sign * derivative;
    return;
  }
  if (&rows.matrix == &kSixIdentity) {  // no product to take
    tangent.block(row, column, rows.count, derivative.cols()) +=
        rows.sign * derivative.middleRows(rows.first, rows.count);
    return;
  }
  const Eigen::Matrix<double, 6, kCols> all = rows.matrix * derivative;
  tangent.block(row, column, rows.count, all.cols()) +=
      rows.sign * all.middleRows(rows.first, rows.count);
}

// rows·v, as the residual's rows at `row` (`add`: added to them).
inline void set_rows(Eigen::Ref<VecX> residual, Index row, const SixRows& rows, const Vec6& v,
                     bool add = false) {
  const Vec6 all = rows.sign * (rows.matrix * v);
  if (add)
    residual.segment(row, rows.count) += all.segment(rows.first, rows.count);
  else
    residual.segment(row, rows.count) = all.segment(rows.first, rows.count);
}

// LoadedBlock::pattern of each kind of block, a joint's or support's plus its p (0…6).
constexpr int kFreeEndPattern = 1;
constexpr int kCorotationalLinkPattern = 2;
constexpr int kRigidLinkPattern = 3;
constexpr int kConstraintJointPattern = 10;
constexpr int kElasticJointPattern = 20;
constexpr int kSupportPattern = 30;
constexpr int kLoadsAlongPattern = 100;  // plus the link's own

// Readies a block's tangent (LoadedBlock::evaluate): sized rows × cols and zeroed where it is of
// another size (true), else left as it is, zero outside the block's pattern (false).
inline bool size_tangent(MatX& tangent, Index rows, Index cols) {
  if (tangent.rows() == rows && tangent.cols() == cols) return false;
  tangent.setZero(rows, cols);
  return true;
}

// The column of end `slot`'s δx, δθ or δW in a block's tangent.
inline Index position_column(Index slot) { return 12 * slot; }
inline Index turn_column(Index slot) { return 12 * slot + 3; }
inline Index wrench_column(Index slot) { return 12 * slot + 6; }

// log(A·Bᵀ) of two turning rotations A, B: δφ = J⁻¹(φ)·(δθ_A − A·Bᵀ·δθ_B).
struct RelativeRotation {
  Vec3 value;
  Mat3 of_first;   // ∂φ/∂δθ_A
  Mat3 of_second;  // ∂φ/∂δθ_B
};
inline RelativeRotation relative_rotation(const Mat3& a, const Mat3& b) {
  const Mat3 product = a * b.transpose();
  RelativeRotation r;
  r.value = rotation_vector<double>(product);
  r.of_first = inverse_left_jacobian<double>(r.value);
  r.of_second = -r.of_first * product;
  return r;
}

// The finite motion of end k relative to end 1 in end 1's axes (§15.4),
// q = [R_1ᵀ·(x_k − x_1); log(R_1ᵀ·R_k)], and its derivatives in [δx; δθ] of either end.
struct RelativeMotion {
  Vec6 value;
  Mat6 of_first;  // ∂q/∂[δx_1; δθ_1]
  Mat6 of_other;  // ∂q/∂[δx_k; δθ_k]
};
inline RelativeMotion relative_motion(const EndState& first, const EndState& other) {
  RelativeMotion q;
  const Mat3 back = first.rotation.transpose();
  const Vec3 arm = other.position - first.position;
  q.value.head<3>() = back * arm;
  const Vec3 phi = rotation_vector<double>(Mat3(back * other.rotation));
  q.value.tail<3>() = phi;
  const Mat3 turn = inverse_left_jacobian<double>(phi) * back;
  q.of_first << -back, back * skew_of<double>(arm), Mat3::Zero(), -turn;
  q.of_other << back, Mat3::Zero(), Mat3::Zero(), turn;
  return q;
}

// The wrench [F; M] = W_k − W_ext,k of an end, taken about the point `about` and turned into
// `axes` (§15.4–15.5): w = [Rᵀ·F; Rᵀ·(M + (x_k − about) × F)], and its derivatives.
struct HeldWrench {
  Vec6 value;
  Mat6 of_wrench;     // ∂w/∂δW_k
  Mat63 of_position;  // ∂w/∂δx_k = −∂w/∂δ(about)
  Mat63 of_turn;      // ∂w/∂δθ of the axes, where they turn with an end
};
inline HeldWrench held_wrench(const EndState& end, const Vec6& external, const Vec3& about,
                              const Mat3& axes) {
  HeldWrench w;
  const Mat3 back = axes.transpose();
  const Vec3 force = end.wrench.head<3>() - external.head<3>();
  const Vec3 moment =
      end.wrench.tail<3>() - external.tail<3>() + (end.position - about).cross(force);
  w.value << back * force, back * moment;
  w.of_wrench << back, Mat3::Zero(), back * skew_of<double>(Vec3(end.position - about)), back;
  w.of_position << Mat3::Zero(), -back * skew_of<double>(force);
  w.of_turn << back * skew_of<double>(force), back * skew_of<double>(moment);
  return w;
}

// Adds rows·∂w into the tangent for the wrench of end `slot` held about end 0's point, its axes
// turning with end 0 where `axes_turn`.
inline void add_held_wrench(MatX& tangent, Index row, const SixRows& rows, const HeldWrench& w,
                            Index slot, bool axes_turn) {
  add_derivative(tangent, row, wrench_column(slot), rows, w.of_wrench);
  if (slot != 0) {  // at end 0 itself the arm x_k − x_0 does not change
    add_derivative(tangent, row, position_column(slot), rows, w.of_position);
    add_derivative(tangent, row, position_column(0), rows, -w.of_position);
  }
  if (axes_turn) add_derivative(tangent, row, turn_column(0), rows, w.of_turn);
}

// Adds Λ·∂w for the wrench of end `slot`, held about end 0's point in end 0's turning axes (Λ:
// FreeDirections::rows, p free directions): its Λ_r rows at `held_row`, its Λ_p rows at
// `free_row`, from one product.
inline void add_held_wrench_split(MatX& tangent, Index held_row, Index free_row, const Mat6& rows,
                                  Index p, const HeldWrench& w, Index slot) {
  const Index r = 6 - p;
  auto add = [&](Index column, const auto& all, double sign) {
    tangent.block(held_row, column, r, all.cols()) += sign * all.bottomRows(r);
    tangent.block(free_row, column, p, all.cols()) += sign * all.topRows(p);
  };
  const Mat6 of_wrench = rows * w.of_wrench;
  add(wrench_column(slot), of_wrench, 1);
  if (slot != 0) {  // at end 0 itself the arm x_k − x_0 does not change
    const Mat63 of_position = rows * w.of_position;
    add(position_column(slot), of_position, 1);
    add(position_column(0), of_position, -1);
  }
  const Mat63 of_turn = rows * w.of_turn;
  add(turn_column(0), of_turn, 1);
}

// The rows rows·Σ_k w_k of a group's wrenches about its first end's point in `axes` (turning
// with the first end where `axes_turn`), into residual and, where given, tangent, at `row`.
inline void add_wrench_sum(const LoadedInputs& in, const std::vector<int>& ends, const Mat3& axes,
                           bool axes_turn, const SixRows& rows, Index row,
                           Eigen::Ref<VecX> residual, MatX* tangent) {
  const EndState& first = in.ends[static_cast<std::size_t>(ends[0])];
  Vec6 sum = Vec6::Zero();
  for (std::size_t k = 0; k < ends.size(); ++k) {
    const auto e = static_cast<std::size_t>(ends[k]);
    const HeldWrench w = held_wrench(in.ends[e], in.external[e], first.position, axes);
    sum += w.value;
    if (tangent) add_held_wrench(*tangent, row, rows, w, static_cast<Index>(k), axes_turn);
  }
  set_rows(residual, row, rows, sum);
}

}  // namespace stiffmsa::detail
