// A flexible link in the loaded mode: the co-rotational element of docs/theory.md §15.2.
#include <cmath>

#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

using Mat7 = Eigen::Matrix<double, 7, 7>;
using Vec7 = Eigen::Matrix<double, 7, 1>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

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
  int pattern() const override { return kCorotationalLinkPattern; }

  // Rows W − ∂E/∂t: the gradient in closed form and, for the tangent, its exact derivative
  // (docs/theory.md §15.2).
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const EndState& i = in.ends[static_cast<std::size_t>(ends_[0])];
    const EndState& j = in.ends[static_cast<std::size_t>(ends_[1])];
    Mat12 second;
    const Vec12 g = gradient(i, j, tangent ? &second : nullptr);
    residual.head<6>() = i.wrench - g.head<6>();
    residual.tail<6>() = j.wrench - g.tail<6>();
    if (!tangent) return;
    // Columns: end i [δx, δθ, δW], end j [δx, δθ, δW].
    size_tangent(*tangent, 12, 24);
    tangent->leftCols<6>() = -second.leftCols<6>();
    tangent->middleCols<6>(12) = -second.rightCols<6>();
    tangent->block<6, 6>(0, 6).setIdentity();
    tangent->block<6, 6>(6, 18).setIdentity();
  }

 private:
  using Row9 = Eigen::Matrix<double, 1, 9>;
  using Jacobian = Eigen::Matrix<double, 3, 9>;  // ∂(3-vector)/∂[δc, δθ_i, δθ_j]

  // ∂E/∂t = [∂E/∂x_i; ∂E/∂θ_i; ∂E/∂x_j; ∂E/∂θ_j] (δθ spatial) at the ends' poses and, where
  // `derivative` is given, its derivative in the same increments (after the multiplicative
  // update), each ingredient's derivative taken along with its value.
  //
  // The co-rotated frame E = [e1 e2 e3]: e1 along the chord c = x_j − x_i (l = |c|), e3 along
  // w = e1 × q with q = ½·(q_i + q_j), q_k = R_k·r0, h = |w| = q·e2, e2 = e3 × e1; the link's
  // rigid rotation Rr = E·E0ᵀ. The deformation z = [φ_i; u; φ_j], φ_k = log(Rrᵀ·R_k),
  // u = l − L0, and the energy's gradient f = ∂E/∂z. A virtual motion turns the frame by
  // δθ_r = Γ·δt and Rrᵀ·R_k by Rrᵀ·(δθ_k − δθ_r) in front, so that
  // δφ_k = J⁻¹(φ_k)·Rrᵀ·(δθ_k − Γ·δt) and f_φk does the work of the moment
  // μ_k = Rr·J⁻¹(φ_k)ᵀ·f_φk, with Γ = e1·γ1ᵀ + e2·γ2ᵀ + e3·γ3ᵀ,
  //   γ2 = [e3, 0, −e3, 0]/l,  γ3 = [−e2, 0, e2, 0]/l  (the chord's turn),
  //   γ1 = [(q·e1)·e3/l, ½·q_i × e3, −(q·e1)·e3/l, ½·q_j × e3]/h  (q's spin about e1).
  // Then ∂E/∂t = [−F, μ_i − ½·s·q_i × e3, F, μ_j − ½·s·q_j × e3] with m = μ_i + μ_j,
  // m_c = e_c·m, s = m_1/h and F = f_u·e1 + (m_2·e3 − m_3·e2)/l + s·(q·e1)/l·e3.
  Vec12 gradient(const EndState& i, const EndState& j, Mat12* derivative) const {
    const Vec3 chord = j.position - i.position;
    const double length = chord.norm();
    const Vec3 e1 = chord / length;
    const Vec3 qi = i.rotation * frame_.col(1), qj = j.rotation * frame_.col(1);
    const Vec3 q = 0.5 * (qi + qj);
    const Vec3 w = e1.cross(q);
    const double across = w.norm();  // h
    const Vec3 e3 = w / across;
    const Vec3 e2 = e3.cross(e1);
    Mat3 current;
    current << e1, e2, e3;
    const Mat3 rigid = current * frame_.transpose();
    const Vec3 phi_i = rotation_vector<double>(Mat3(rigid.transpose() * i.rotation));
    const Vec3 phi_j = rotation_vector<double>(Mat3(rigid.transpose() * j.rotation));
    const double u = length - length_;
    Vec7 z;
    z << phi_i, u, phi_j;
    Vec7 f = reduced_ * z;
    // A beam's chord shortens as it bends: u_eff = u + b, b = L0/30·(2|θ_i⊥|² − θ_i⊥·θ_j⊥ +
    // 2|θ_j⊥|²), the cubic's arc length beyond its chord, with θ⊥ the end rotations across the
    // unloaded chord n0 (§15.2); the energy ½·EA/L0·(u_eff² − u²) is added, whose gradient is
    // EA/L0·b along u and EA/L0·u_eff·∂b/∂θ along the rotations.
    Vec3 ti = Vec3::Zero(), tj = Vec3::Zero();
    double bow = 0, rigidity = 0, bow_scale = 0;
    const Mat3 across_n0 = Mat3::Identity() - frame_.col(0) * frame_.col(0).transpose();
    if (link_.axial) {
      ti = across_n0 * phi_i;
      tj = across_n0 * phi_j;
      bow = length_ / 30 * (2 * ti.squaredNorm() - ti.dot(tj) + 2 * tj.squaredNorm());
      rigidity = *link_.axial / length_;
      bow_scale = rigidity * (u + bow) * length_ / 30;
      f.head<3>() += bow_scale * (4 * ti - tj);
      f(3) += rigidity * bow;
      f.tail<3>() += bow_scale * (4 * tj - ti);
    }
    const Vec3 vi = f.head<3>(), vj = f.tail<3>();
    const Mat3 inverse_i = inverse_left_jacobian<double>(phi_i);
    const Mat3 inverse_j = inverse_left_jacobian<double>(phi_j);
    const Vec3 mu_i = rigid * (inverse_i.transpose() * vi);
    const Vec3 mu_j = rigid * (inverse_j.transpose() * vj);
    const Vec3 m = mu_i + mu_j;
    const double m1 = e1.dot(m), m2 = e2.dot(m), m3 = e3.dot(m);
    const double spin = m1 / across;
    const double q_along = q.dot(e1);
    const double lift = spin * q_along / length;  // s·(q·e1)/l
    const Vec3 force = f(3) * e1 + (m2 * e3 - m3 * e2) / length + lift * e3;
    const Vec3 arm_i = qi.cross(e3), arm_j = qj.cross(e3);
    Vec12 g;
    g << -force, mu_i - 0.5 * spin * arm_i, force, mu_j - 0.5 * spin * arm_j;
    if (!derivative) return g;

    // The same formulas differentiated, step by step, in b = [δc, δθ_i, δθ_j]: everything sees
    // the positions through the chord c = x_j − x_i only, so ∂/∂x_j = ∂/∂c = −∂/∂x_i.
    const Mat3 identity = Mat3::Identity();
    Row9 d_length = Row9::Zero();
    d_length.head<3>() = e1.transpose();
    const Mat3 chord_turn = (identity - e1 * e1.transpose()) / length;
    // e1 sees δc only and q_k δθ_k only: the products with their derivatives are taken over
    // those three columns alone (the others' terms are zeros).
    Jacobian d_e1 = Jacobian::Zero();
    d_e1.leftCols<3>() = chord_turn;
    const Mat3 turn_qi = -skew_of<double>(qi), turn_qj = -skew_of<double>(qj);  // ∂q_k/∂δθ_k
    const Mat3 half_turn_qi = 0.5 * turn_qi, half_turn_qj = 0.5 * turn_qj;      // ∂q/∂δθ_k
    const Mat3 turn_e1 = skew_of<double>(e1);
    Jacobian d_w;
    d_w.leftCols<3>() = -(skew_of<double>(q) * chord_turn);
    d_w.middleCols<3>(3) = turn_e1 * half_turn_qi;
    d_w.rightCols<3>() = turn_e1 * half_turn_qj;
    const Row9 d_across = e3.transpose() * d_w;
    const Jacobian d_e3 = ((identity - e3 * e3.transpose()) / across) * d_w;
    Jacobian d_e2 = -(turn_e1 * d_e3);
    d_e2.leftCols<3>() = skew_of<double>(e3) * chord_turn + d_e2.leftCols<3>();
    Row9 gamma1, gamma2 = Row9::Zero(), gamma3 = Row9::Zero();
    gamma1 << -q_along / length * e3.transpose(), 0.5 * arm_i.transpose(), 0.5 * arm_j.transpose();
    gamma1 /= across;
    gamma2.head<3>() = -e3.transpose() / length;
    gamma3.head<3>() = e2.transpose() / length;
    const Jacobian frame_turn = e1 * gamma1 + e2 * gamma2 + e3 * gamma3;  // Γ
    const Mat3 back_i = inverse_i * rigid.transpose(), back_j = inverse_j * rigid.transpose();
    Jacobian d_phi_i = -back_i * frame_turn, d_phi_j = -back_j * frame_turn;
    d_phi_i.middleCols<3>(3) += back_i;
    d_phi_j.rightCols<3>() += back_j;
    Eigen::Matrix<double, 7, 9> d_z;
    d_z << d_phi_i, d_length, d_phi_j;
    Eigen::Matrix<double, 7, 9> d_f = reduced_ * d_z;
    if (link_.axial) {
      const Jacobian d_ti = across_n0 * d_phi_i, d_tj = across_n0 * d_phi_j;
      const Vec3 bow_i = 4 * ti - tj, bow_j = 4 * tj - ti;
      const Row9 d_bow = length_ / 30 * (bow_i.transpose() * d_ti + bow_j.transpose() * d_tj);
      const Row9 d_bow_scale = rigidity * length_ / 30 * (d_length + d_bow);
      d_f.topRows<3>() += bow_i * d_bow_scale + bow_scale * (4 * d_ti - d_tj);
      d_f.row(3) += rigidity * d_bow;
      d_f.bottomRows<3>() += bow_j * d_bow_scale + bow_scale * (4 * d_tj - d_ti);
    }
    // μ_k = Rr·J⁻ᵀ(φ_k)·v_k turns with the frame: δμ_k = Rr·δ(J⁻ᵀ·v_k) − [μ_k×]·Γ.
    const Jacobian d_mu_i =
        rigid * (inverse_i.transpose() * d_f.topRows<3>() + slope(phi_i, vi) * d_phi_i) -
        skew_of<double>(mu_i) * frame_turn;
    const Jacobian d_mu_j =
        rigid * (inverse_j.transpose() * d_f.bottomRows<3>() + slope(phi_j, vj) * d_phi_j) -
        skew_of<double>(mu_j) * frame_turn;
    const Jacobian d_m = d_mu_i + d_mu_j;
    Row9 d_m1 = e1.transpose() * d_m;
    d_m1.head<3>() += m.transpose() * chord_turn;
    const Row9 d_m2 = e2.transpose() * d_m + m.transpose() * d_e2;
    const Row9 d_m3 = e3.transpose() * d_m + m.transpose() * d_e3;
    const Row9 d_spin = (d_m1 - spin * d_across) / across;
    Row9 d_q_along;
    d_q_along << q.transpose() * chord_turn, e1.transpose() * half_turn_qi,
        e1.transpose() * half_turn_qj;
    const Row9 d_lift = (q_along * d_spin + spin * d_q_along - lift * d_length) / length;
    const Jacobian d_force =
        e1 * d_f.row(3) + f(3) * d_e1 + (e3 * d_m2 + m2 * d_e3 - e2 * d_m3 - m3 * d_e2) / length -
        ((m2 * e3 - m3 * e2) / (length * length)) * d_length + e3 * d_lift + lift * d_e3;
    const Mat3 turn_e3 = skew_of<double>(e3);
    Jacobian d_arm_i = skew_of<double>(qi) * d_e3, d_arm_j = skew_of<double>(qj) * d_e3;
    d_arm_i.middleCols<3>(3) -= turn_e3 * turn_qi;
    d_arm_j.rightCols<3>() -= turn_e3 * turn_qj;
    Eigen::Matrix<double, 12, 9> d_g;
    d_g << -d_force, d_mu_i - 0.5 * (arm_i * d_spin + spin * d_arm_i), d_force,
        d_mu_j - 0.5 * (arm_j * d_spin + spin * d_arm_j);
    derivative->leftCols<3>() = -d_g.leftCols<3>();
    derivative->middleCols<3>(3) = d_g.middleCols<3>(3);
    derivative->middleCols<3>(6) = d_g.leftCols<3>();
    derivative->rightCols<3>() = d_g.rightCols<3>();
    return g;
  }

  // ∂(J⁻¹(φ)ᵀ·v)/∂φ for J⁻¹(φ)ᵀ·v = v + ½·φ × v + β·φ × (φ × v):
  // −½·[v×] + β·((φ·v)·I + φ·vᵀ − 2·v·φᵀ) + (φ × (φ × v))·β'/ϑ·φᵀ.
  static Mat3 slope(const Vec3& phi, const Vec3& v) {
    const double x = phi.squaredNorm();
    return -0.5 * skew_of<double>(v) +
           inverse_jacobian_coefficient(x) *
               (phi.dot(v) * Mat3::Identity() + phi * v.transpose() - 2 * v * phi.transpose()) +
           (phi.cross(phi.cross(v)) * inverse_jacobian_slope(x)) * phi.transpose();
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
