#pragma once
// How a loaded block gets its tangent. The built-in blocks write it out from the pieces at the
// end of this file (docs/theory.md §15.1). Rows written once as a template on the scalar can
// instead be evaluated by `evaluate_block`: in double for the residual, or with forward-mode
// duals whose variables are the increments [δx; δθ; δW] of the block's ends at zero.
#include <utility>

#include "elements/finite_rotation.hpp"
#include "elements/loaded_blocks.hpp"

namespace stiffmsa::detail {

template <class T>
using Vec6T = Eigen::Matrix<T, 6, 1>;
template <class T>
using VecXT = Eigen::Matrix<T, Eigen::Dynamic, 1>;

// A link end's state with its increments as variables 12·slot … 12·slot + 11 of `count`.
template <class T>
struct EndT {
  Vec3T<T> x;
  Mat3T<T> rotation;
  Vec6T<T> wrench;
};

template <class T>
T variable(double value, int count, int index) {
  if constexpr (std::is_same_v<T, double>) {
    return value;
  } else {
    return T(value, count, index);
  }
}

template <class T>
EndT<T> end_with_increments(const EndState& s, int slot, int count) {
  EndT<T> e;
  Vec3T<T> turn;
  for (int i = 0; i < 3; ++i) {
    e.x(i) = variable<T>(s.position(i), count, 12 * slot + i);
    turn(i) = variable<T>(0.0, count, 12 * slot + 3 + i);
  }
  for (int i = 0; i < 6; ++i) e.wrench(i) = variable<T>(s.wrench(i), count, 12 * slot + 6 + i);
  e.rotation = turned(s.rotation, turn);
  return e;
}

template <class T>
Vec6T<T> external_of(const Vec6& w) {
  return w.cast<T>();
}

// Evaluates `rows(ends, r)` (ends: EndT<T> of the block's ends in order; r: VecXT<T> of `count`
// rows) into `residual` and, where given, `tangent`.
template <int N, class Rows>
void evaluate_with_duals(const LoadedInputs& in, const std::vector<int>& ends, Index count,
                         Rows&& rows, Eigen::Ref<VecX> residual, MatX* tangent) {
  if (!tangent) {
    std::vector<EndT<double>> e;
    e.reserve(ends.size());
    for (std::size_t k = 0; k < ends.size(); ++k)
      e.push_back(end_with_increments<double>(in.ends[static_cast<std::size_t>(ends[k])],
                                              static_cast<int>(k), 0));
    VecX r(count);
    rows(e, r);
    residual = r;
    return;
  }
  using T = Dual<N>;
  const int variables = 12 * static_cast<int>(ends.size());
  std::vector<EndT<T>> e;
  e.reserve(ends.size());
  for (std::size_t k = 0; k < ends.size(); ++k)
    e.push_back(end_with_increments<T>(in.ends[static_cast<std::size_t>(ends[k])],
                                       static_cast<int>(k), variables));
  VecXT<T> r(count);
  rows(e, r);
  tangent->setZero(count, variables);
  for (Index i = 0; i < count; ++i) {
    residual(i) = r(i).value();
    if (r(i).derivatives().size() == variables) tangent->row(i) = r(i).derivatives().transpose();
  }
}

// The same, with the dual of the block's size: fixed for one and two ends (no allocation per
// operation), dynamic beyond.
template <class Rows>
void evaluate_block(const LoadedInputs& in, const std::vector<int>& ends, Index count, Rows&& rows,
                    Eigen::Ref<VecX> residual, MatX* tangent) {
  if (ends.size() == 1)
    evaluate_with_duals<12>(in, ends, count, std::forward<Rows>(rows), residual, tangent);
  else if (ends.size() == 2)
    evaluate_with_duals<24>(in, ends, count, std::forward<Rows>(rows), residual, tangent);
  else
    evaluate_with_duals<Eigen::Dynamic>(in, ends, count, std::forward<Rows>(rows), residual,
                                        tangent);
}

// The rows of a wrench w = [F; M] about `from`, taken about `to` and turned into the axes of
// `rotation` (columns: those axes in global ones): [Rᵀ·F; Rᵀ·(M + (from − to) × F)].
template <class T, class Rotation>
Vec6T<T> wrench_in_axes(const Vec6T<T>& w, const Vec3T<T>& from, const Vec3T<T>& to,
                        const Rotation& rotation) {
  Vec6T<T> out;
  const Vec3T<T> force = w.template head<3>();
  const Vec3T<T> moment = w.template tail<3>() + (from - to).cross(force);
  out.template head<3>() = rotation.transpose() * force;
  out.template tail<3>() = rotation.transpose() * moment;
  return out;
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
  if (&rows.matrix == &kSixIdentity) {  // no product to take
    tangent.block(row, column, rows.count, derivative.cols()) +=
        rows.sign * derivative.middleRows(rows.first, rows.count);
    return;
  }
  const Eigen::Matrix<double, 6, Derivative::ColsAtCompileTime> all = rows.matrix * derivative;
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
