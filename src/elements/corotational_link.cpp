// A flexible link in the loaded mode: the co-rotational element of docs/theory.md §15.2.
#include <cmath>

#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

using Mat7 = Eigen::Matrix<double, 7, 7>;
template <class T>
using Vec12T = Eigen::Matrix<T, 12, 1>;
using Variable = Dual<12>;  // the 12 increments [δx_i, δθ_i, δx_j, δθ_j] of a Newton step

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
    // d̄ = P·z with z = [φ_i; u; φ_j] (7): ½·d̄ᵀ·K·d̄ = ½·zᵀ·(Pᵀ·K·P)·z.
    Eigen::Matrix<double, 12, 7> p = Eigen::Matrix<double, 12, 7>::Zero();
    p.block<3, 3>(3, 0).setIdentity();
    p.block<3, 1>(6, 3) = chord;
    p.block<3, 3>(9, 4).setIdentity();
    reduced_ = p.transpose() * link.stiffness * p;
  }
  Index equation_count() const override { return 12; }
  const std::vector<int>& ends() const override { return ends_; }

  // Rows W − ∂E/∂t: the gradient in closed form (`gradient`), and its exact derivative, the
  // tangent, by one forward pass of 12 duals over that formula (docs/theory.md §15.2).
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const EndState& i = in.ends[static_cast<std::size_t>(ends_[0])];
    const EndState& j = in.ends[static_cast<std::size_t>(ends_[1])];
    if (!tangent) {
      const Vec12T<double> g = gradient<double>(i.position, i.rotation, j.position, j.rotation);
      residual.head<6>() = i.wrench - g.head<6>();
      residual.tail<6>() = j.wrench - g.tail<6>();
      return;
    }
    Vec3T<Variable> xi, xj, turn_i, turn_j;
    for (int k = 0; k < 3; ++k) {
      xi(k) = Variable(i.position(k), 12, k);
      turn_i(k) = Variable(0.0, 12, 3 + k);
      xj(k) = Variable(j.position(k), 12, 6 + k);
      turn_j(k) = Variable(0.0, 12, 9 + k);
    }
    const Vec12T<Variable> g =
        gradient<Variable>(xi, turned(i.rotation, turn_i), xj, turned(j.rotation, turn_j));
    // Columns: end i [δx, δθ, δW], end j [δx, δθ, δW].
    tangent->setZero(12, 24);
    for (int m = 0; m < 12; ++m) {
      residual(m) = (m < 6 ? i.wrench(m) : j.wrench(m - 6)) - g(m).value();
      tangent->row(m).segment<6>(0) = -g(m).derivatives().head<6>().transpose();
      tangent->row(m).segment<6>(12) = -g(m).derivatives().tail<6>().transpose();
    }
    tangent->block<6, 6>(0, 6).setIdentity();
    tangent->block<6, 6>(6, 18).setIdentity();
  }

 private:
  // ∂E/∂t = [∂E/∂x_i; ∂E/∂θ_i; ∂E/∂x_j; ∂E/∂θ_j] (δθ spatial) at the ends' poses.
  //
  // The co-rotated frame E = [e1 e2 e3]: e1 along the chord c = x_j − x_i (l = |c|), e3 along
  // e1 × q with q = ½·(R_i + R_j)·r0, e2 = e3 × e1; the link's rigid rotation Rr = E·E0ᵀ. The
  // deformation z = [φ_i; u; φ_j], φ_k = log(Rrᵀ·R_k), u = l − L0, and the energy's gradient
  // f = ∂E/∂z. A virtual motion turns Rrᵀ·R_k by Rrᵀ·(δθ_k − δθ_r) in front, so that
  // δφ_k = J⁻¹(φ_k)·Rrᵀ·(δθ_k − δθ_r) and f_φk does the work of the moment
  // μ_k = Rr·J⁻¹(φ_k)ᵀ·f_φk; the frame's own turn δθ_r = Σ_c e_c·γ_cᵀ·δt has
  //   γ2 = [e3, 0, −e3, 0]/l,  γ3 = [−e2, 0, e2, 0]/l  (the chord's turn),
  //   γ1 = [(q·e1)·e3/l, ½·q_i × e3, −(q·e1)·e3/l, ½·q_j × e3]/(q·e2)  (the spin of q about e1,
  //   q_k = R_k·r0),
  // so that ∂E/∂t = f_u·[−e1, 0, e1, 0] + [0, μ_i, 0, μ_j] − Σ_c γ_c·(e_c·(μ_i + μ_j)).
  template <class T>
  Vec12T<T> gradient(const Vec3T<T>& xi, const Mat3T<T>& ri, const Vec3T<T>& xj,
                     const Mat3T<T>& rj) const {
    const Vec3T<T> chord = xj - xi;
    const T length = chord.norm();
    const Vec3T<T> e1 = chord / length;
    const Vec3T<T> reference_unloaded = frame_.col(1).cast<T>();
    const Vec3T<T> qi = ri * reference_unloaded, qj = rj * reference_unloaded;
    const Vec3T<T> q = T(0.5) * (qi + qj);
    Vec3T<T> e3 = e1.cross(q);
    const T across_chord = e3.norm();  // q·e2
    e3 /= across_chord;
    const Vec3T<T> e2 = e3.cross(e1);
    Mat3T<T> current;
    current.col(0) = e1;
    current.col(1) = e2;
    current.col(2) = e3;
    const Mat3T<T> rigid = current * frame_.transpose().cast<T>();
    const Vec3T<T> phi_i = rotation_vector<T>(Mat3T<T>(rigid.transpose() * ri));
    const Vec3T<T> phi_j = rotation_vector<T>(Mat3T<T>(rigid.transpose() * rj));
    const T u = length - T(length_);
    Eigen::Matrix<T, 7, 1> z;
    z << phi_i, u, phi_j;
    Eigen::Matrix<T, 7, 1> f = reduced_.cast<T>() * z;
    if (link_.axial) {
      // A beam's chord shortens as it bends: u_eff = u + b, b = L0/30·(2|θ_i⊥|² − θ_i⊥·θ_j⊥ +
      // 2|θ_j⊥|²), the cubic's arc length beyond its chord, with θ⊥ the end rotations across
      // the unloaded chord n0 (§15.2); the energy ½·EA/L0·(u_eff² − u²) is added, whose
      // gradient is EA/L0·(b along u, u_eff·∂b/∂θ along the rotations).
      const Vec3T<T> n0 = frame_.col(0).cast<T>();
      const Vec3T<T> ti = phi_i - n0 * n0.dot(phi_i);
      const Vec3T<T> tj = phi_j - n0 * n0.dot(phi_j);
      const T bow =
          T(length_ / 30.0) * (T(2) * ti.squaredNorm() - ti.dot(tj) + T(2) * tj.squaredNorm());
      const T rigidity = T(*link_.axial / length_);
      const T scale = rigidity * (u + bow) * T(length_ / 30.0);
      f.template head<3>() += scale * (T(4) * ti - tj);
      f(3) += rigidity * bow;
      f.template tail<3>() += scale * (T(4) * tj - ti);
    }
    const Vec3T<T> mu_i =
        rigid * inverse_left_jacobian_transposed_times<T>(phi_i, f.template head<3>());
    const Vec3T<T> mu_j =
        rigid * inverse_left_jacobian_transposed_times<T>(phi_j, f.template tail<3>());
    const Vec3T<T> moment = mu_i + mu_j;
    const T spin = e1.dot(moment) / across_chord;  // (e1·m)/(q·e2)
    const Vec3T<T> force = f(3) * e1 + (e2.dot(moment) * e3 - e3.dot(moment) * e2) / length +
                           spin * (q.dot(e1) / length) * e3;
    Vec12T<T> g;
    g.template segment<3>(0) = -force;
    g.template segment<3>(3) = mu_i - T(0.5) * spin * qi.cross(e3);
    g.template segment<3>(6) = force;
    g.template segment<3>(9) = mu_j - T(0.5) * spin * qj.cross(e3);
    return g;
  }

  std::vector<int> ends_;
  CorotationalLink link_;
  double length_ = 0;
  Mat3 frame_;    // columns n0, r0, n0 × r0
  Mat7 reduced_;  // Pᵀ·K·P
};

}  // namespace

std::unique_ptr<LoadedBlock> make_corotational_link(int end_i, int end_j,
                                                    const CorotationalLink& link) {
  return std::make_unique<CorotationalLinkBlock>(end_i, end_j, link);
}

}  // namespace stiffmsa::detail
