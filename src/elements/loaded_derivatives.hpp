#pragma once
// How a loaded block gets its tangent: its residual rows are written once, as a template on the
// scalar, and evaluated in double for the residual or with forward-mode duals, whose variables
// are the increments [δx; δθ; δW] of its ends at zero, for the residual and its derivatives.
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

}  // namespace stiffmsa::detail
