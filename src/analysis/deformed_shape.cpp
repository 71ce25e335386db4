#include "stiffmsa/deformed_shape.hpp"

#include "elements/beam_element.hpp"
#include "model/link_ends.hpp"

namespace stiffmsa {

CentreLineMotion centre_line_motion(bool bends, const Vec3& from, const Vec3& to,
                                    const Vec6& from_deflection, const Vec6& to_deflection,
                                    double xi) {
  const Vec3 d1 = from_deflection.head<3>(), r1 = from_deflection.tail<3>();
  const Vec3 d2 = to_deflection.head<3>(), r2 = to_deflection.tail<3>();
  CentreLineMotion motion;
  motion.displacement = (1 - xi) * d1 + xi * d2;
  motion.rotation = (1 - xi) * r1 + xi * r2;
  const Vec3 chord = to - from;
  const double length = chord.norm();
  if (!bends || length == 0) return motion;

  const Vec3 e = chord / length;
  const auto across = [&](const Vec3& v) -> Vec3 { return v - e * e.dot(v); };
  // Slopes of the transverse displacement at the ends: a small rotation φ turns the axis e by φ ×
  // e.
  const Vec3 slope1 = r1.cross(e), slope2 = r2.cross(e);
  const double xi2 = xi * xi, xi3 = xi2 * xi;
  const double h1 = 1 - 3 * xi2 + 2 * xi3, h2 = xi - 2 * xi2 + xi3;
  const double h3 = 3 * xi2 - 2 * xi3, h4 = xi3 - xi2;
  // Their derivatives with respect to ξ, for the slope inside the span.
  const double dh1 = -6 * xi + 6 * xi2, dh2 = 1 - 4 * xi + 3 * xi2;
  const double dh3 = 6 * xi - 6 * xi2, dh4 = 3 * xi2 - 2 * xi;
  const Vec3 transverse =
      h1 * across(d1) + h2 * length * slope1 + h3 * across(d2) + h4 * length * slope2;
  const Vec3 slope = (dh1 * across(d1) + dh3 * across(d2)) / length + dh2 * slope1 + dh4 * slope2;
  motion.displacement = e * e.dot(motion.displacement) + transverse;
  // The rotation about e (twist) is linear; across e it is the one that turns e by the slope.
  motion.rotation = e * e.dot(motion.rotation) + e.cross(slope);
  return motion;
}

bool bends(const LinkKind& kind) { return std::holds_alternative<BeamLink>(kind); }

ModelPoints::ModelPoints(const Model& model)
    : index_(std::make_unique<const detail::ModelIndex>(model)) {}
ModelPoints::~ModelPoints() = default;

int ModelPoints::of_link_end(std::size_t link, LinkEnd end) const {
  return index_->point_of_end(detail::LinkEndRef{static_cast<int>(link), end}.id());
}

int ModelPoints::of_name(std::string_view point) const { return index_->point_position(point); }

Vec3 beam_y_axis(const Vec3& from, const Vec3& to, const std::optional<Vec3>& zref) {
  return detail::link_axes(from, to, zref).row(1).transpose();
}

}  // namespace stiffmsa
