// Loads along links in the loaded mode (docs/theory.md §15.9): dead loads in global axes whose
// clamp wrenches follow the link's current geometry, added to the link's rows with their exact
// derivatives (the load stiffness).
#include <cmath>

#include "elements/beam_element.hpp"
#include "elements/beam_loads.hpp"
#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

using Vec12d = Eigen::Matrix<double, 12, 1>;
using Outer = NestedDual;

// The transverse shape of a beam between its chord's ends, per unit length and per unit slope
// at end i (first) and end j (second): N₂/L and N₄/L of §12.1, shear included through φ.
std::pair<double, double> slope_shapes(double xi, double phi) {
  const double x2 = xi * xi, x3 = x2 * xi, d = 1 + phi;
  return {(xi - 2 * x2 + x3 + phi / 2 * (xi - x2)) / d, (-x2 + x3 - phi / 2 * (xi - x2)) / d};
}

// The link's current shape (§15.9): its chord, the co-rotated axes (columns) and, for a beam,
// the slopes t_k·a of its ends' turned axes n0 along the co-rotated y and z axes.
template <class T>
struct Current {
  T length;
  Mat3T<T> axes;
  Eigen::Matrix<T, 2, 1> slope_i, slope_j;
};

template <class T>
Current<T> current_shape(const LoadedLinkShape& shape, const Vec3T<T>& xi, const Mat3T<T>& ri,
                         const Vec3T<T>& xj, const Mat3T<T>& rj) {
  Current<T> c;
  const Vec3T<T> chord = xj - xi;
  c.length = chord.norm();
  c.axes.col(0) = chord / c.length;
  // The second axis: the unloaded one turned by the mean of the ends' rotations, made
  // orthogonal to the chord (the co-rotated frame of §15.2 built on the beam's own y axis).
  const Mat3& unloaded = shape.unloaded_axes();
  const Vec3T<T> mean = T(0.5) * ((ri + rj) * unloaded.row(1).transpose().cast<T>());
  Vec3T<T> y = mean - c.axes.col(0) * c.axes.col(0).dot(mean);
  y /= y.norm();
  c.axes.col(1) = y;
  c.axes.col(2) = c.axes.col(0).cross(y);
  c.slope_i.setZero();
  c.slope_j.setZero();
  if (shape.kind() == LoadedLinkShape::Kind::beam) {
    const Vec3T<T> n0 = unloaded.row(0).transpose().cast<T>();
    const Vec3T<T> ti = ri * n0, tj = rj * n0;
    for (int a = 0; a < 2; ++a) {
      c.slope_i(a) = ti.dot(c.axes.col(1 + a));
      c.slope_j(a) = tj.dot(c.axes.col(1 + a));
    }
  }
  return c;
}

}  // namespace

LoadedLinkShape::LoadedLinkShape(const Link& link, const Vec3& from, const Vec3& to)
    : d0_(to - from), length_((to - from).norm()) {
  if (std::holds_alternative<RigidLink>(link.kind)) {
    kind_ = Kind::rigid;
    axes_ = link_axes(from, to, std::nullopt);
  } else if (const auto* beam = std::get_if<BeamLink>(&link.kind)) {
    kind_ = Kind::beam;
    axes_ = link_axes(from, to, beam->zref);
    constants_ = beam_constants(*beam, length_);
  } else {
    kind_ = Kind::chord;
    axes_ = link_axes(from, to, std::nullopt);
  }
}

Vec3 LoadedLinkShape::point(const EndState& i, const EndState& j, double xi) const {
  if (kind_ == Kind::rigid) return i.position + xi * (i.rotation * d0_);
  const Current<double> c =
      current_shape<double>(*this, i.position, i.rotation, j.position, j.rotation);
  Vec3 p = i.position + xi * (j.position - i.position);
  const double phi[2] = {constants_.phi_y, constants_.phi_z};
  for (int a = 0; a < 2; ++a) {
    const auto [hi, hj] = slope_shapes(xi, phi[a]);
    p += length_ * (hi * c.slope_i(a) + hj * c.slope_j(a)) * c.axes.col(1 + a);
  }
  return p;
}

Mat3 LoadedLinkShape::axes(const EndState& i, const EndState& j) const {
  if (kind_ == Kind::rigid) return axes_ * i.rotation.transpose();
  return current_shape<double>(*this, i.position, i.rotation, j.position, j.rotation)
      .axes.transpose();
}

namespace {

// The loads along one link reduced to what its clamp wrenches need (§15.9), per unit load
// factor: the lever-rule shares Q_i, Q_j of the forces along the chord, for a beam the works
// B_{k,a} of the forces on its transverse shapes (slope at end k, plane a = y, z), the couples of
// a non-beam link (taken at its `from` end) and a beam's point moments with their clamp
// wrenches per unit moment (unloaded global axes).
struct ReducedLoads {
  Vec3 share_i = Vec3::Zero(), share_j = Vec3::Zero();
  Vec3 work_i[2] = {Vec3::Zero(), Vec3::Zero()};
  Vec3 work_j[2] = {Vec3::Zero(), Vec3::Zero()};
  Vec3 couple = Vec3::Zero();
  struct Moment {
    Vec3 moment;
    Eigen::Matrix<double, 12, 3> clamp;  // clamp wrenches per unit moment
  };
  std::vector<Moment> moments;
};

class LinkWithLoadsBlock final : public LoadedBlock {
 public:
  LinkWithLoadsBlock(std::unique_ptr<LoadedBlock> link, LoadedLinkShape shape,
                     const std::vector<LoadAlongLink>& loads)
      : link_(std::move(link)), shape_(std::move(shape)) {
    const double length = shape_.length();
    const bool beam = shape_.kind() == LoadedLinkShape::Kind::beam;
    const BeamConstants& c = shape_.constants();
    const double phi[2] = {c.phi_y, c.phi_z};
    for (const LoadAlongLink& load : loads) {
      if (const auto* q = std::get_if<DistributedLinkLoad>(&load)) {
        r_.share_i += length * (2 * q->from + q->to) / 6;
        r_.share_j += length * (q->from + 2 * q->to) / 6;
        if (!beam) continue;
        // ∫ q(ξ)·H_k(ξ) dξ·L², H_k the slope shapes: the closed forms of §12.2 over L.
        for (int a = 0; a < 2; ++a) {
          const double d = 1 + phi[a], l2 = length * length;
          r_.work_i[a] += l2 * ((6 + 5 * phi[a]) * q->from + (4 + 5 * phi[a]) * q->to) / (120 * d);
          r_.work_j[a] -= l2 * ((4 + 5 * phi[a]) * q->from + (6 + 5 * phi[a]) * q->to) / (120 * d);
        }
        continue;
      }
      const auto& p = std::get<PointLinkLoad>(load);
      r_.share_i += (1 - p.position) * p.force;
      r_.share_j += p.position * p.force;
      if (beam) {
        for (int a = 0; a < 2; ++a) {
          const auto [hi, hj] = slope_shapes(p.position, phi[a]);
          r_.work_i[a] += length * hi * p.force;
          r_.work_j[a] += length * hj * p.force;
        }
        if (!p.moment.isZero(0)) {
          ReducedLoads::Moment m{p.moment, {}};
          const Mat3& axes = shape_.unloaded_axes();
          for (int k = 0; k < 3; ++k) {
            const Vec12 local =
                beam_fixed_end_forces(c, PointLoad{Vec3::Zero(), axes * Vec3::Unit(k), p.position});
            for (int part = 0; part < 4; ++part)
              m.clamp.block<3, 1>(3 * part, k) = axes.transpose() * local.segment<3>(3 * part);
          }
          r_.moments.push_back(m);
        }
      } else {
        r_.couple += p.moment;
      }
    }
  }

  Index equation_count() const override { return link_->equation_count(); }
  const std::vector<int>& ends() const override { return link_->ends(); }
  int pattern() const override { return kLoadsAlongPattern + link_->pattern(); }

  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    link_->evaluate(in, residual, tangent);
    const double lambda = in.load_factor;
    if (lambda == 0) return;
    const EndState& i = in.ends[static_cast<std::size_t>(ends()[0])];
    const EndState& j = in.ends[static_cast<std::size_t>(ends()[1])];
    switch (shape_.kind()) {
      case LoadedLinkShape::Kind::rigid: add_rigid(i, lambda, residual, tangent); return;
      case LoadedLinkShape::Kind::chord:
        // The lever rule along the chord: clamp wrenches −Q_i, −Q_j and the couples at the
        // `from` end, dead, whatever the geometry (no load stiffness).
        residual.segment<3>(0) += lambda * r_.share_i;
        residual.segment<3>(3) += lambda * r_.couple;
        residual.segment<3>(6) += lambda * r_.share_j;
        return;
      case LoadedLinkShape::Kind::beam: add_beam(i, j, lambda, residual, tangent); return;
    }
  }

 private:
  // The load rides with the rigid link, at x_i + ξ·R_i·d0: its resultant Q_i + Q_j and its
  // moment about x_i, (R_i·d0) × Q_j + ΣM, enter the link's balance rows (7–12, §15.3).
  void add_rigid(const EndState& i, double lambda, Eigen::Ref<VecX> residual, MatX* tangent) const {
    const Vec3 arm = i.rotation * shape_.unloaded_chord();
    residual.segment<3>(6) += lambda * (r_.share_i + r_.share_j);
    residual.segment<3>(9) += lambda * (arm.cross(r_.share_j) + r_.couple);
    if (!tangent) return;
    // δ(arm × Q) = (δθ_i × arm) × Q = [Q×]·[arm×]·δθ_i
    tangent->block<3, 3>(9, 3) += lambda * skew_of<double>(r_.share_j) * skew_of<double>(arm);
  }

  // A beam: the clamp wrenches are the gradient of the load's potential V = −Σ q·x over the
  // points x(ξ) of the chord and the transverse shape of the end slopes (§15.9), plus the
  // point moments' fixed-end wrenches turned with the co-rotated frame.
  void add_beam(const EndState& i, const EndState& j, double lambda, Eigen::Ref<VecX> residual,
                MatX* tangent) const {
    Vec3T<Outer> xi, xj;
    Mat3T<Outer> ri, rj;
    nested_moved_pose(i, 0, xi, ri);
    nested_moved_pose(j, 6, xj, rj);
    const auto c = current_shape<Outer>(shape_, xi, ri, xj, rj);
    Outer work = xi.dot(r_.share_i.cast<Outer>()) + xj.dot(r_.share_j.cast<Outer>());
    for (int a = 0; a < 2; ++a)
      work += c.slope_i(a) * c.axes.col(1 + a).dot(r_.work_i[a].cast<Outer>()) +
              c.slope_j(a) * c.axes.col(1 + a).dot(r_.work_j[a].cast<Outer>());
    // Clamp wrench ∂V/∂t = −∂work/∂t; the rows W − ∂E/∂t − clamp gain +∂work/∂t.
    Vec12d clamp = -work.value().derivatives();
    Mat12 clamp_derivative;
    for (int b = 0; b < 12; ++b) clamp_derivative.col(b) = -work.derivatives()(b).derivatives();
    if (!r_.moments.empty()) add_moments(c, clamp, clamp_derivative);
    residual.head<6>() -= lambda * clamp.head<6>();
    residual.segment<6>(6) -= lambda * clamp.tail<6>();
    if (!tangent) return;
    for (int b = 0; b < 12; ++b) {
      const int column = b < 6 ? b : b + 6;
      tangent->col(column).head<12>() -= lambda * clamp_derivative.col(b);
    }
  }

  // A point moment M on a beam: its fixed-end wrenches of §12.2 for the moment seen in the
  // co-rotated frame Rc, turned back by Rc, the forces scaled by L0/l so that the wrenches
  // balance the couple about the current chord exactly.
  void add_moments(const Current<Outer>& c, Vec12d& clamp, Mat12& clamp_derivative) const {
    const Mat3T<Outer> turn = c.axes * shape_.unloaded_axes().cast<Outer>();
    const Outer lever = Outer(shape_.length()) / c.length;
    for (const ReducedLoads::Moment& m : r_.moments) {
      const Vec3T<Outer> seen = turn.transpose() * m.moment.cast<Outer>();
      for (int part = 0; part < 4; ++part) {
        Vec3T<Outer> w = turn * (m.clamp.block<3, 3>(3 * part, 0).cast<Outer>() * seen);
        if (part % 2 == 0) w *= lever;
        for (int k = 0; k < 3; ++k) {
          clamp(3 * part + k) += w(k).value().value();
          for (int b = 0; b < 12; ++b)
            clamp_derivative(3 * part + k, b) += w(k).derivatives()(b).value();
        }
      }
    }
  }

  std::unique_ptr<LoadedBlock> link_;
  LoadedLinkShape shape_;
  ReducedLoads r_;
};

}  // namespace

std::unique_ptr<LoadedBlock> with_loads_along(std::unique_ptr<LoadedBlock> link_block,
                                              const Link& link, const Vec3& from, const Vec3& to,
                                              const std::vector<LoadAlongLink>& loads) {
  if (loads.empty()) return link_block;
  return std::make_unique<LinkWithLoadsBlock>(std::move(link_block),
                                              LoadedLinkShape(link, from, to), loads);
}

}  // namespace stiffmsa::detail
