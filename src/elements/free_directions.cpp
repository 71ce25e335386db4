#include "elements/free_directions.hpp"

#include <Eigen/Cholesky>

#include "elements/element_block.hpp"
#include "tolerances.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <initializer_list>

namespace stiffmsa::detail {

namespace {

Vec3 unit(const Vec3& v, const char* what) {
  const double n = v.norm();
  if (!(n > 0) || !std::isfinite(n))
    throw InputError({}, what, "must be a nonzero finite 3-vector");
  return v / n;
}

Vec6 translation_row(const Vec3& a) {
  Vec6 r = Vec6::Zero();
  r.head<3>() = a;
  return r;
}
Vec6 rotation_row(const Vec3& a) {
  Vec6 r = Vec6::Zero();
  r.tail<3>() = a;
  return r;
}

}  // namespace

void planar_axes(const Vec3& normal, Vec3& t1, Vec3& t2) {
  const Vec3 n = unit(normal, "normal");
  // The global axis least aligned with n; the first of x, y, z on a tie.
  int least = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) < std::abs(n[least])) least = i;
  const Vec3 g = Vec3::Unit(least);
  t1 = n.cross(g).normalized();
  t2 = n.cross(t1);
}

FreeDirections rotations_across(const Vec3& axis, const Vec3& across) {
  // Below this sine of the angle between `across` and the axis, its part across the axis has
  // lost too many digits to set a direction.
  constexpr double kLeastSine = 0.1;
  const Vec3 u = axis.isZero(0) ? Vec3::UnitZ() : axis.normalized();
  Vec3 t1 = across.normalized() - across.normalized().dot(u) * u, t2;
  if (t1.norm() < kLeastSine) {
    planar_axes(u, t1, t2);
  } else {
    t1.normalize();
    t2 = u.cross(t1);
  }
  return free_directions(Kinematics::universal(t1, t2));
}

namespace {

// Up to three axes, on the stack.
struct Axes {
  Vec3 axis[3];
  int count = 0;
  void add(const Vec3& a) { axis[count++] = a; }
  const Vec3* begin() const { return axis; }
  const Vec3* end() const { return axis + count; }
};

// Orthonormal axes spanning the orthogonal complement in 3-space of independent unit axes
// (orthogonal to each other where there are three).
Axes complement(const Axes& axes) {
  Axes rest;
  switch (axes.count) {
    case 0:
      for (int i = 0; i < 3; ++i) rest.add(Vec3::Unit(i));
      break;
    case 1: {
      Vec3 t1, t2;
      planar_axes(axes.axis[0], t1, t2);
      rest.add(t1);
      rest.add(t2);
      break;
    }
    case 2: {
      // Across u and v's part orthogonal to u rather than u × v, whose rounding would tilt it
      // off u and v by ε/sin θ where the axes are nearly parallel (θ down to 2e-9 is allowed).
      const Vec3& u = axes.axis[0];
      const Vec3 across = (axes.axis[1] - axes.axis[1].dot(u) * u).normalized();
      rest.add(u.cross(across).normalized());
      break;
    }
    default: break;
  }
  return rest;
}

}  // namespace

FreeDirections free_directions(const Kinematics& k) {
  DirectionRows free;
  // Λ_p on the stack: this runs for every joint of every pose.
  const auto set_rows = [&](std::initializer_list<Vec6> rows) {  // at most 3 rows here
    free.resize(static_cast<Index>(rows.size()), 6);
    Index i = 0;
    for (const Vec6& row : rows) free.row(i++) = row.transpose();
  };
  switch (k.type) {
    case JointType::rigid: set_rows({}); break;
    case JointType::revolute: set_rows({rotation_row(unit(k.axis, "axis"))}); break;
    case JointType::prismatic: set_rows({translation_row(unit(k.axis, "axis"))}); break;
    case JointType::cylindrical: {
      const Vec3 a = unit(k.axis, "axis");
      set_rows({translation_row(a), rotation_row(a)});
      break;
    }
    case JointType::universal:
      set_rows({rotation_row(unit(k.axis, "axes[0]")), rotation_row(unit(k.axis_b, "axes[1]"))});
      break;
    case JointType::spherical:
      set_rows(
          {rotation_row(Vec3::UnitX()), rotation_row(Vec3::UnitY()), rotation_row(Vec3::UnitZ())});
      break;
    case JointType::planar: {
      Vec3 t1, t2;
      planar_axes(k.normal, t1, t2);
      set_rows({translation_row(t1), translation_row(t2), rotation_row(unit(k.normal, "normal"))});
      break;
    }
    case JointType::custom:
      if (k.free_rows.size() > 6)
        throw InputError({}, "free", "at most 6 free directions can be given");
      free.resize(static_cast<Index>(k.free_rows.size()), 6);
      for (std::size_t i = 0; i < k.free_rows.size(); ++i)
        free.row(static_cast<Index>(i)) = k.free_rows[i].transpose();
      break;
  }
  FreeDirections d;  // rigid: Λ_r = I
  const Index p = free.rows();
  if (p == 0) return d;
  // Independence: the built-in types are orthonormal by construction except a universal
  // joint, whose two unit axes u, v have singular values √(1 ± |u·v|); their ratio is
  // ‖u × v‖/(1 + |u·v|), written so that nearly parallel axes do not cancel (closed form: this
  // runs for every joint of every pose). Custom rows get an SVD.
  double smallest_over_largest = 1;
  if (k.type == JointType::universal) {
    const Vec3 u = free.row(0).tail<3>().transpose(), v = free.row(1).tail<3>().transpose();
    smallest_over_largest = u.cross(v).norm() / (1 + std::abs(u.dot(v)));
  } else if (k.type == JointType::custom) {
    const Eigen::JacobiSVD<DirectionRows> svd(free);
    const auto& s = svd.singularValues();
    smallest_over_largest = s(0) > 0 ? s(p - 1) / s(0) : 0.0;
  }
  if (!(smallest_over_largest > kRankTolerance))
    throw InputError({}, "free", "the free directions are linearly dependent");
  d.p = p;
  d.rows.topRows(p) = free;
  if (k.type == JointType::custom) {
    // The last 6−p columns of a full QR of Λ_pᵀ span the orthogonal complement of its rows.
    const Eigen::HouseholderQR<Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>> qr(
        free.transpose());
    const Mat6 q = qr.householderQ();
    d.rows.bottomRows(6 - p) = q.rightCols(6 - p).transpose();
    return d;
  }
  // A built-in type frees translations along some axes and rotations about some: Λ_r holds
  // translations along the complement of the first and rotations about the complement of the
  // second, in closed form (this runs for every joint of every pose).
  Axes translations, rotations;
  for (Index i = 0; i < p; ++i) {
    if (free.row(i).head<3>().isZero(0))
      rotations.add(free.row(i).tail<3>().transpose());
    else
      translations.add(free.row(i).head<3>().transpose());
  }
  Index row = p;
  for (const Vec3& axis : complement(translations))
    d.rows.row(row++) = translation_row(axis).transpose();
  for (const Vec3& axis : complement(rotations)) d.rows.row(row++) = rotation_row(axis).transpose();
  return d;
}

SpringCompliance spring_compliance(const FreeDirections& directions, const SmallMat& spring,
                                   const std::optional<VecX>& preload) {
  SpringCompliance result{Mat6::Zero(), Vec6::Zero()};
  if (directions.p == 0) return result;
  // Λ_r spans the orthogonal complement of Λ_p's rows, so Λ_r·δ = 0 makes δ = Λ_pᵀ·q, and
  // G·K·Λ_p·Λ_pᵀ·q = G·K·G·q: a p×p symmetric positive definite system instead of M's 6×6.
  const SmallMat gkg = spring * directions.free().transpose();
  if (directions.p == 1) {  // a revolute or prismatic spring: G·K·G is a number
    const auto row = directions.free().row(0);
    result.compliance.noalias() = row.transpose() * (row / gkg(0, 0));
    if (preload)
      result.preload_motion =
          row.transpose() * (directions.gram()(0, 0) * (*preload)(0) / gkg(0, 0));
    return result;
  }
  const Eigen::LLT<SmallMat> llt(gkg);
  const SmallMat q = llt.solve(SmallMat(directions.free()));
  result.compliance.noalias() = directions.free().transpose() * q;
  if (preload)
    result.preload_motion.noalias() =
        directions.free().transpose() * llt.solve(directions.gram() * *preload);
  return result;
}

}  // namespace stiffmsa::detail
