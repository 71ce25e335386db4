#include "elements/beam_loads.hpp"

#include <array>
#include <cmath>
#include <string>

#include "stiffmsa/number_text.hpp"

namespace stiffmsa::detail {

namespace {

enum { u1 = 0, v1, w1, tx1, ty1, tz1, u2, v2, w2, tx2, ty2, tz2 };

void require_fraction(double value, const char* key, const char* what) {
  if (!(value >= 0 && value <= 1))  // also refuses NaN
    throw InputError({}, key,
                     std::string(what) + " must be a fraction of the length in [0, 1], got " +
                         shortest_text(value));
}

// The transverse displacement and section rotation of the unloaded beam (exact for Timoshenko's
// beam, Euler–Bernoulli's at phi = 0) under a unit value of one end degree of freedom,
// order [d1, r1, d2, r2], in the x-y plane's convention d' = r (for Euler–Bernoulli).
struct PlaneShapes {
  std::array<double, 4> displacement;
  std::array<double, 4> rotation;
};

PlaneShapes plane_shapes(double xi, double phi, double L) {
  const double x2 = xi * xi, x3 = x2 * xi, d = 1 + phi;
  PlaneShapes s;
  s.displacement = {(1 - 3 * x2 + 2 * x3 + phi * (1 - xi)) / d,
                    L * (xi - 2 * x2 + x3 + phi / 2 * (xi - x2)) / d,
                    (3 * x2 - 2 * x3 + phi * xi) / d, L * (-x2 + x3 - phi / 2 * (xi - x2)) / d};
  s.rotation = {6 * (x2 - xi) / (d * L), (1 - 4 * xi + 3 * x2 + phi * (1 - xi)) / d,
                -6 * (x2 - xi) / (d * L), (-2 * xi + 3 * x2 + phi * xi) / d};
  return s;
}

// Adds one bending plane's reactions [d1, r1, d2, r2], computed in the x-y plane's convention
// with the rotation r' = s·r: s = −1 for the x-z plane (w' = −θy), as in beam_local_stiffness.
// A moment doing work on r' does s times as much on r, hence s on the rotation entries.
void put_plane(Vec12& f, int d1, int r1, int d2, int r2, double s, const std::array<double, 4>& r) {
  f(d1) += r[0];
  f(r1) += s * r[1];
  f(d2) += r[2];
  f(r2) += s * r[3];
}

Vec12 distributed_fixed_end_forces(const BeamConstants& c, const DistributedLoad& load) {
  const double L = c.length;
  Vec12 f = Vec12::Zero();
  f(u1) = -L * (2 * load.q_from.x() + load.q_to.x()) / 6;
  f(u2) = -L * (load.q_from.x() + 2 * load.q_to.x()) / 6;
  // ∫ N_i q dx with the exact shape functions, in closed form (theory.md §12.2).
  auto plane = [L](double q1, double q2, double phi) {
    const double d = 1 + phi;
    return std::array<double, 4>{-L * ((21 + 20 * phi) * q1 + (9 + 10 * phi) * q2) / (60 * d),
                                 -L * L * ((6 + 5 * phi) * q1 + (4 + 5 * phi) * q2) / (120 * d),
                                 -L * ((9 + 10 * phi) * q1 + (21 + 20 * phi) * q2) / (60 * d),
                                 L * L * ((4 + 5 * phi) * q1 + (6 + 5 * phi) * q2) / (120 * d)};
  };
  put_plane(f, v1, tz1, v2, tz2, +1.0, plane(load.q_from.y(), load.q_to.y(), c.phi_y));
  put_plane(f, w1, ty1, w2, ty2, -1.0, plane(load.q_from.z(), load.q_to.z(), c.phi_z));
  return f;
}

Vec12 point_fixed_end_forces(const BeamConstants& c, const PointLoad& load) {
  require_fraction(load.position, "position", "a point load's position");
  const double a = load.position, L = c.length;
  Vec12 f = Vec12::Zero();
  f(u1) = -load.force.x() * (1 - a);
  f(u2) = -load.force.x() * a;
  f(tx1) = -load.moment.x() * (1 - a);
  f(tx2) = -load.moment.x() * a;
  // Betti: the reaction at degree of freedom i is −(force · N_i(a) + moment · rotation_i(a)).
  auto plane = [&](double force, double moment, double phi) {
    const PlaneShapes shapes = plane_shapes(a, phi, L);
    std::array<double, 4> r{};
    for (int i = 0; i < 4; ++i)
      r[i] = -(force * shapes.displacement[i] + moment * shapes.rotation[i]);
    return r;
  };
  put_plane(f, v1, tz1, v2, tz2, +1.0, plane(load.force.y(), load.moment.z(), c.phi_y));
  // In the x-z plane the moment about y turns the rotation r' = −θy the other way.
  put_plane(f, w1, ty1, w2, ty2, -1.0, plane(load.force.z(), -load.moment.y(), c.phi_z));
  return f;
}

}  // namespace

Vec12 beam_fixed_end_forces(const BeamConstants& c, const BeamLoad& load) {
  if (const auto* distributed = std::get_if<DistributedLoad>(&load))
    return distributed_fixed_end_forces(c, *distributed);
  return point_fixed_end_forces(c, std::get<PointLoad>(load));
}

Vec6 beam_internal_forces(double length, const Vec6& from_end_forces,
                          std::span<const BeamLoad> loads, double station) {
  require_fraction(station, "station", "a station");
  const double x = station * length;
  const Vec3 ex = Vec3::UnitX();
  // Everything acting on the part [0, x], moments about the cut's centroid x·ex; the cut's
  // wrench balances it.
  Vec3 force = from_end_forces.head<3>();
  Vec3 moment = from_end_forces.tail<3>() + (-x * ex).cross(from_end_forces.head<3>());
  for (const BeamLoad& load : loads) {
    if (const auto* distributed = std::get_if<DistributedLoad>(&load)) {
      const Vec3 slope = (distributed->q_to - distributed->q_from) / length;
      force += distributed->q_from * x + slope * (x * x / 2);
      // ∫₀ˣ (s − x)·q(s) ds
      moment += ex.cross(-distributed->q_from * (x * x / 2) - slope * (x * x * x / 6));
    } else {
      const auto& point = std::get<PointLoad>(load);
      require_fraction(point.position, "position", "a point load's position");
      if (point.position < station) {
        force += point.force;
        moment += point.moment + ((point.position * length - x) * ex).cross(point.force);
      }
    }
  }
  Vec6 internal;
  internal << -force, -moment;
  return internal;
}

}  // namespace stiffmsa::detail
