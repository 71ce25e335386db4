#include "elements/beam_element.hpp"
#include "tolerances.hpp"

#include <cmath>

namespace stiffmsa::detail {

Mat3 link_axes(const Vec3& from, const Vec3& to, const std::optional<Vec3>& zref) {
  const Vec3 x = (to - from).normalized();
  Vec3 reference = Vec3::UnitZ();
  if (zref)
    reference = *zref;
  else if (x.cross(Vec3::UnitZ()).norm() < kReferenceParallel)
    reference = Vec3::UnitX();
  const Vec3 y_raw = reference.cross(x);
  if (!(y_raw.norm() > kParallelTolerance * reference.norm()))
    throw InputError({}, "zref", "zref must not be parallel to the link");
  const Vec3 y = y_raw.normalized();
  Mat3 axes;
  axes.row(0) = x.transpose();
  axes.row(1) = y.transpose();
  axes.row(2) = x.cross(y).transpose();
  return axes;
}

Mat12 link_rotation12(const Mat3& axes) {
  Mat12 T = Mat12::Zero();
  for (int b = 0; b < 4; ++b) T.block<3, 3>(3 * b, 3 * b) = axes;
  return T;
}

BeamConstants beam_constants(const BeamLink& beam, double length) {
  const SectionProperties s = section_properties(beam.section);
  BeamConstants c;
  c.length = length;
  c.E = beam.material.E;
  c.G = shear_modulus(beam.material);
  c.A = s.A;
  c.Iy = s.Iy;
  c.Iz = s.Iz;
  c.J = s.J;
  if (beam.shear) {
    if (!s.Asy || !s.Asz)
      throw InputError({}, "shear", "a Timoshenko beam needs the shear areas Asy and Asz");
    const double L2 = length * length;
    c.phi_y = 12 * c.E * c.Iz / (c.G * *s.Asy * L2);
    c.phi_z = 12 * c.E * c.Iy / (c.G * *s.Asz * L2);
  }
  return c;
}

Mat12 beam_local_stiffness(const BeamConstants& c) {
  const double L = c.length, L2 = L * L, L3 = L2 * L;
  Mat12 k = Mat12::Zero();
  enum { u1 = 0, v1, w1, tx1, ty1, tz1, u2, v2, w2, tx2, ty2, tz2 };

  const double axial = c.E * c.A / L;
  k(u1, u1) = k(u2, u2) = axial;
  k(u1, u2) = k(u2, u1) = -axial;

  const double torsion = c.G * c.J / L;
  k(tx1, tx1) = k(tx2, tx2) = torsion;
  k(tx1, tx2) = k(tx2, tx1) = -torsion;

  // Bending in one plane: displacement d, rotation r; `s` = +1 where d' = +r (x-y plane,
  // v' = θz) and −1 where d' = −r (x-z plane, w' = −θy).
  auto bending = [&](int d1, int r1, int d2, int r2, double EI, double phi, double s) {
    const double f = EI / ((1 + phi) * L3);
    const double a = 12 * f, b = 6 * L * f * s, near = (4 + phi) * L2 * f, far = (2 - phi) * L2 * f;
    // clang-format off
    k(d1, d1) = a;   k(d1, r1) = b;     k(d1, d2) = -a;  k(d1, r2) = b;
    k(r1, d1) = b;   k(r1, r1) = near;  k(r1, d2) = -b;  k(r1, r2) = far;
    k(d2, d1) = -a;  k(d2, r1) = -b;    k(d2, d2) = a;   k(d2, r2) = -b;
    k(r2, d1) = b;   k(r2, r1) = far;   k(r2, d2) = -b;  k(r2, r2) = near;
    // clang-format on
  };
  bending(v1, tz1, v2, tz2, c.E * c.Iz, c.phi_y, +1.0);
  bending(w1, ty1, w2, ty2, c.E * c.Iy, c.phi_z, -1.0);
  return k;
}

Mat6 beam_local_compliance(const BeamConstants& c) {
  const double L = c.length, L2 = L * L;
  Mat6 f = Mat6::Zero();
  f(0, 0) = L / (c.E * c.A);
  f(3, 3) = L / (c.G * c.J);
  // x-y plane (v, θz, Iz): v' = θz. x-z plane (w, θy, Iy): w' = −θy. Shear adds φ·L³/(12EI).
  f(1, 1) = L2 * L / (3 * c.E * c.Iz) * (1 + c.phi_y / 4);
  f(5, 5) = L / (c.E * c.Iz);
  f(1, 5) = f(5, 1) = L2 / (2 * c.E * c.Iz);
  f(2, 2) = L2 * L / (3 * c.E * c.Iy) * (1 + c.phi_z / 4);
  f(4, 4) = L / (c.E * c.Iy);
  f(2, 4) = f(4, 2) = -L2 / (2 * c.E * c.Iy);
  return f;
}

Mat6 rotation6(const Mat3& axes) {
  Mat6 r = Mat6::Zero();
  r.block<3, 3>(0, 0) = axes;
  r.block<3, 3>(3, 3) = axes;
  return r;
}

Mat6 beam_global_compliance(const BeamLink& beam, const Vec3& from, const Vec3& to) {
  const Mat6 R = rotation6(link_axes(from, to, beam.zref));
  return R.transpose() * beam_local_compliance(beam_constants(beam, (to - from).norm())) * R;
}

Mat12 beam_global_stiffness(const BeamLink& beam, const Vec3& from, const Vec3& to) {
  const Mat12 T = link_rotation12(link_axes(from, to, beam.zref));
  const Mat12 local = beam_local_stiffness(beam_constants(beam, (to - from).norm()));
  return T.transpose() * local * T;
}

}  // namespace stiffmsa::detail
