#pragma once
// Loads along a beam (theory.md §12): the exact fixed-end forces of a beam clamped at both ends,
// Euler–Bernoulli or Timoshenko, and the internal forces at a station of a loaded beam.
// Kernels only: not yet reachable from model files.
#include <span>
#include <variant>

#include "elements/beam_element.hpp"

namespace stiffmsa::detail {

using Vec12 = Eigen::Matrix<double, 12, 1>;

// A force per unit length in local axes, varying linearly from q_from at the `from` end to
// q_to at the `to` end; q_from == q_to is a uniform load.
struct DistributedLoad {
  Vec3 q_from = Vec3::Zero();
  Vec3 q_to = Vec3::Zero();
  static DistributedLoad uniform(const Vec3& q) { return {q, q}; }
};

// A force and a moment in local axes at `position`, a fraction of the length from the `from` end.
struct PointLoad {
  Vec3 force = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
  double position = 0;
};

using BeamLoad = std::variant<DistributedLoad, PointLoad>;

// The end forces of the beam clamped at both ends under the load: the wrenches the clamps exert
// on the beam, local axes, order per end [Fx, Fy, Fz, Mx, My, Mz] — the sign convention of
// beam_local_stiffness's end forces, so that a loaded beam's end forces are k·d + these.
// Exact for the beam of beam_local_stiffness (shear deformation through phi_y, phi_z).
// Throws InputError when a point load's position is outside [0, 1].
Vec12 beam_fixed_end_forces(const BeamConstants& c, const BeamLoad& load);

// Internal forces [N, Vy, Vz, T, My, Mz] at `station` (a fraction of the length from the
// `from` end): the wrench, about the section's centroid, that the part beyond the station
// exerts on the part before it (N > 0 is tension; My = −E·Iy·w'', Mz = E·Iz·v'' for
// Euler–Bernoulli), from the `from` end's forces (the first six of the end-force 12-vector)
// and the loads along the beam. A point load at the station itself is not yet counted (the
// value is the limit from the `from` side). Throws InputError when `station` or a point
// load's position is outside [0, 1].
Vec6 beam_internal_forces(double length, const Vec6& from_end_forces,
                          std::span<const BeamLoad> loads, double station);

}  // namespace stiffmsa::detail
