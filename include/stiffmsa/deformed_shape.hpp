#pragma once
// The deformed shape between a link's ends, from the deflections a solve gives at the ends: what
// the viewer draws and the VTK file carries along each link.
#include <memory>
#include <optional>
#include <string_view>

#include "stiffmsa/model.hpp"

namespace stiffmsa {

namespace detail {
class ModelIndex;
}

// The small motion of one point of a link's centre line: displacement and rotation (global).
struct CentreLineMotion {
  Vec3 displacement = Vec3::Zero();
  Vec3 rotation = Vec3::Zero();
};

// The motion of the point at the fraction `xi` (0 at `from`, 1 at `to`) of the straight line
// between a link's ends, given the deflections Δt = [Δp; Δφ] of both ends.
// A beam (`bends`) carries no load between its ends, so an Euler–Bernoulli beam bends exactly
// as the cubic (Hermite) shape functions say: transverse displacement cubic with the end
// slopes Δφ × e, axial displacement and twist linear (a Timoshenko beam's shear adds a part
// the cubic leaves out). A rigid link moves rigidly, which is the linear interpolation of its
// ends; a CAD link's interior is unknown and is drawn by the same straight chord.
CentreLineMotion centre_line_motion(bool bends, const Vec3& from, const Vec3& to,
                                    const Vec6& from_deflection, const Vec6& to_deflection,
                                    double xi);

// Whether a link kind bends along its length (beams) or is drawn as a chord between its ends.
bool bends(const LinkKind& kind);

// Where a model's parts are drawn: the position in `model.points` of the point at each link end
// and of each named point, by the rule the analyses use (a repeated name finds the first point
// bearing it). Refers to the model, which must outlive it.
class ModelPoints {
 public:
  explicit ModelPoints(const Model& model);
  ~ModelPoints();
  ModelPoints(const ModelPoints&) = delete;
  ModelPoints& operator=(const ModelPoints&) = delete;
  int of_link_end(std::size_t link, LinkEnd end) const;  // −1 where the link names no point
  int of_name(std::string_view point) const;             // −1 where no point bears the name

 private:
  std::unique_ptr<const detail::ModelIndex> index_;
};

// A beam's local y axis in global axes, where its section's width b lies
// (docs/model-format.md): from the beam's ends and its optional reference vector `zref`.
Vec3 beam_y_axis(const Vec3& from, const Vec3& to, const std::optional<Vec3>& zref);

}  // namespace stiffmsa
