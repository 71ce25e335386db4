#include "elements/beam_geometric.hpp"

namespace stiffmsa::detail {

Mat12 beam_geometric_stiffness(const BeamConstants& c, double axial_force) {
  const double L = c.length, L2 = L * L, N = axial_force;
  Mat12 k = Mat12::Zero();
  enum { u1 = 0, v1, w1, tx1, ty1, tz1, u2, v2, w2, tx2, ty2, tz2 };

  const double torsion = N * (c.Iy + c.Iz) / (c.A * L);
  k(tx1, tx1) = k(tx2, tx2) = torsion;
  k(tx1, tx2) = k(tx2, tx1) = -torsion;

  // N·∫ N_i' N_j' dx of the transverse shape functions, one plane; `s` as in
  // beam_local_stiffness (+1 where d' = +r, −1 where d' = −r).
  auto bending = [&](int d1, int r1, int d2, int r2, double phi, double s) {
    const double f = N / (L * (1 + phi) * (1 + phi));
    const double a = f * (6.0 / 5 + 2 * phi + phi * phi);
    const double b = f * s * L / 10;
    const double near = f * L2 * (2.0 / 15 + phi / 6 + phi * phi / 12);
    const double far = -f * L2 * (1.0 / 30 + phi / 6 + phi * phi / 12);
    // clang-format off
    k(d1, d1) = a;   k(d1, r1) = b;     k(d1, d2) = -a;  k(d1, r2) = b;
    k(r1, d1) = b;   k(r1, r1) = near;  k(r1, d2) = -b;  k(r1, r2) = far;
    k(d2, d1) = -a;  k(d2, r1) = -b;    k(d2, d2) = a;   k(d2, r2) = -b;
    k(r2, d1) = b;   k(r2, r1) = far;   k(r2, d2) = -b;  k(r2, r2) = near;
    // clang-format on
  };
  bending(v1, tz1, v2, tz2, c.phi_y, +1.0);
  bending(w1, ty1, w2, ty2, c.phi_z, -1.0);
  return k;
}

}  // namespace stiffmsa::detail

namespace stiffmsa::detail {

Mat12 beam_global_geometric_stiffness(const BeamLink& beam, const Vec3& from, const Vec3& to,
                                      double axial_force) {
  const Mat12 T = link_rotation12(link_axes(from, to, beam.zref));
  const Mat12 local =
      beam_geometric_stiffness(beam_constants(beam, (to - from).norm()), axial_force);
  return T.transpose() * local * T;
}

double beam_axial_force(const Vec3& from, const Vec3& to, const Vec3& force_from,
                        const Vec3& force_to) {
  const Vec3 x = (to - from).normalized();
  return 0.5 * (force_to - force_from).dot(x);
}

}  // namespace stiffmsa::detail
