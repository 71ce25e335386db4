// A flexible link in the loaded mode: the co-rotational element of docs/theory.md §15.2.
#include <cmath>

#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

using Inner = Dual<12>;
using Outer = Dual2<12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

// A scalar of value v whose inner derivative `inner` and outer derivative `outer` are 1 (−1:
// none): the inner variables a are the increments of the virtual motion (the gradient, W), the
// outer ones b those of the Newton step (the tangent).
Outer seeded(double v, int inner, int outer) {
  Inner value(v, Vec12::Zero());
  if (inner >= 0) value.derivatives()(inner) = 1;
  Eigen::Matrix<Inner, 12, 1> derivatives;
  for (int k = 0; k < 12; ++k) derivatives(k) = Inner(0.0, Vec12::Zero());
  if (outer >= 0) derivatives(outer) = Inner(1.0, Vec12::Zero());
  return Outer(value, derivatives);
}

// An end's pose moved by increments a (inner) and b (outer) of 6 each, from variable `first`:
// x + a_x + b_x and (I + [a_θ×])·(I + [b_θ×])·R.
void moved_pose(const EndState& s, int first, Vec3T<Outer>& x, Mat3T<Outer>& rotation) {
  Vec3T<Outer> a, b;
  for (int i = 0; i < 3; ++i) {
    x(i) = seeded(s.position(i), first + i, first + i);
    a(i) = seeded(0, first + 3 + i, -1);
    b(i) = seeded(0, -1, first + 3 + i);
  }
  const Mat3T<Outer> start = s.rotation.cast<Outer>();
  const Mat3T<Outer> after_b = start + skew_of(b) * start;
  rotation = after_b + skew_of(a) * after_b;
}

// A unit vector across `axis` (unit): the global axis least aligned with it, made orthogonal.
Vec3 across(const Vec3& axis) {
  int least = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(axis[i]) < std::abs(axis[least])) least = i;
  const Vec3 g = Vec3::Unit(least);
  return (g - g.dot(axis) * axis).normalized();
}

class CorotationalLinkBlock final : public LoadedBlock {
 public:
  CorotationalLinkBlock(int end_i, int end_j, const CorotationalLink& link)
      : ends_{end_i, end_j}, link_(link) {
    length_ = link.d0.norm();
    const Vec3 chord = link.d0 / length_;
    const Vec3 reference = across(chord);
    frame_.col(0) = chord;
    frame_.col(1) = reference;
    frame_.col(2) = chord.cross(reference);
  }
  Index equation_count() const override { return 12; }
  const std::vector<int>& ends() const override { return ends_; }

  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const EndState& i = in.ends[static_cast<std::size_t>(ends_[0])];
    const EndState& j = in.ends[static_cast<std::size_t>(ends_[1])];
    Vec3T<Outer> xi, xj;
    Mat3T<Outer> ri, rj;
    moved_pose(i, 0, xi, ri);
    moved_pose(j, 6, xj, rj);
    // E = ½·d̄ᵀ·K·d̄ (+ a beam's bowing) by the chain rule on d̄'s first and mixed second
    // derivatives, so that K meets plain numbers only: with A = ∂d̄/∂a, B = ∂d̄/∂b, f = K·d̄,
    // ∂E/∂a = Aᵀ·f and ∂²E/∂a∂b = Aᵀ·K·B + Σ_m f_m·∂²d̄_m/∂a∂b.
    Eigen::Matrix<Outer, 12, 1> d;
    Outer bow_energy;
    deformation(xi, ri, xj, rj, d, bow_energy);
    Mat12 a_part, b_part;
    Vec12 value;
    for (int m = 0; m < 12; ++m) {
      value(m) = d(m).value().value();
      a_part.row(m) = d(m).value().derivatives().transpose();
      for (int b = 0; b < 12; ++b) b_part(m, b) = d(m).derivatives()(b).value();
    }
    const Vec12 force = link_.stiffness * value;
    Vec12 gradient = a_part.transpose() * force + bow_energy.value().derivatives();
    residual.head<6>() = i.wrench - gradient.head<6>();
    residual.tail<6>() = j.wrench - gradient.tail<6>();
    if (!tangent) return;
    Mat12 second = a_part.transpose() * link_.stiffness * b_part;
    for (int m = 0; m < 12; ++m)
      for (int b = 0; b < 12; ++b) second.col(b) += force(m) * d(m).derivatives()(b).derivatives();
    for (int b = 0; b < 12; ++b) second.col(b) += bow_energy.derivatives()(b).derivatives();
    // Columns: end i [δx, δθ, δW], end j [δx, δθ, δW].
    tangent->setZero(12, 24);
    for (int b = 0; b < 12; ++b) {
      const int column = b < 6 ? b : b + 6;
      tangent->col(column).noalias() = -second.col(b);
    }
    tangent->block<6, 6>(0, 6).setIdentity();
    tangent->block<6, 6>(6, 18).setIdentity();
  }

 private:
  // The co-rotated frame: its first axis along the chord x_j − x_i, its second the part
  // across the chord of the unloaded second axis turned by the mean of the ends' rotations.
  // Rr = [e1 e2 e3]·[n0 r0 n0×r0]ᵀ is the link's rigid rotation; what is left of each end's
  // rotation and of the chord's length is the deformation d̄.
  // d̄ and, for a beam, the energy of its bowing beyond ½·d̄ᵀ·K·d̄ (zero for other links).
  template <class T>
  void deformation(const Vec3T<T>& xi, const Mat3T<T>& ri, const Vec3T<T>& xj, const Mat3T<T>& rj,
                   Eigen::Matrix<T, 12, 1>& d, T& bow_energy) const {
    const Vec3T<T> chord = xj - xi;
    const T length = chord.norm();
    const Vec3T<T> e1 = chord / length;
    const Vec3T<T> reference_unloaded = frame_.col(1).cast<T>();
    const Vec3T<T> q = T(0.5) * ((ri + rj) * reference_unloaded);
    Vec3T<T> e3 = e1.cross(q);
    e3 /= e3.norm();
    const Vec3T<T> e2 = e3.cross(e1);
    Mat3T<T> current;
    current.col(0) = e1;
    current.col(1) = e2;
    current.col(2) = e3;
    const Mat3T<T> rigid = current * frame_.transpose().cast<T>();
    const Mat3T<T> left_i = rigid.transpose() * ri;
    const Mat3T<T> left_j = rigid.transpose() * rj;
    for (int k = 0; k < 3; ++k) d(k) = T(0.0);
    d.template segment<3>(3) = rotation_vector<T>(left_i);
    d.template segment<3>(6) = rigid.transpose() * chord - link_.d0.cast<T>();
    d.template segment<3>(9) = rotation_vector<T>(left_j);
    bow_energy = T(0.0);
    if (link_.axial) {
      // A beam's chord shortens as it bends: u_eff = u + L/30·(2|θ_i⊥|² − θ_i⊥·θ_j⊥ +
      // 2|θ_j⊥|²), the cubic's arc length beyond its chord, with θ⊥ the end rotations across
      // the unloaded chord n0 (§15.2). Its energy replaces the axial ½·EA/L·u².
      const Vec3T<T> n0 = frame_.col(0).cast<T>();
      const Vec3T<T> ti = d.template segment<3>(3) - n0 * n0.dot(d.template segment<3>(3));
      const Vec3T<T> tj = d.template segment<3>(9) - n0 * n0.dot(d.template segment<3>(9));
      const T u = length - T(length_);
      const T bow =
          T(length_ / 30.0) * (T(2) * ti.squaredNorm() - ti.dot(tj) + T(2) * tj.squaredNorm());
      const T stretch = u + bow;
      bow_energy = T(0.5 * *link_.axial / length_) * (stretch * stretch - u * u);
    }
  }

  std::vector<int> ends_;
  CorotationalLink link_;
  double length_ = 0;
  Mat3 frame_;  // columns n0, r0, n0 × r0
};

}  // namespace

std::unique_ptr<LoadedBlock> make_corotational_link(int end_i, int end_j,
                                                    const CorotationalLink& link) {
  return std::make_unique<CorotationalLinkBlock>(end_i, end_j, link);
}

}  // namespace stiffmsa::detail
