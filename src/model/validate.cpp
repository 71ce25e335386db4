// Every defect that can be found on a Model without solving it, whether the model came from a
// file or from the C++ API (model-format.md, sections.md). Key paths name the user's entities;
// locations come from the entities' Origin, so file models point at the line.
#include "stiffmsa/validate.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "model/link_ends.hpp"
#include "model/suggest.hpp"
#include "model/value_checks.hpp"

namespace stiffmsa {
namespace {

constexpr double kParallelTolerance = 1e-9;   // |a × b| of unit vectors
constexpr double kRankTolerance = 1e-9;       // smallest over largest singular value
constexpr double kMatrixTolerance = 1e-9;     // symmetry, semi-definiteness: relative to max|M|
constexpr double kDefiniteTolerance = 1e-12;  // smallest over largest eigenvalue
constexpr double kFreeFreeTolerance = 1e-6;   // ‖K·R‖₂ relative to ‖K‖₂·‖R‖₂
constexpr double kLengthTolerance = 1e-12;    // relative to max(1, model extent)

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string end_name(const Model& model, const detail::LinkEndRef& end) {
  return model.links[static_cast<std::size_t>(end.link)].name + "." + to_string(end.end);
}

// The location of `key`, else of the nearest enclosing key recorded ("section.D", then
// "section"), else of the entity itself.
SourceLocation locate(const Origin& origin, std::string key) {
  while (!key.empty()) {
    if (auto it = origin.key_locations.find(key); it != origin.key_locations.end())
      return it->second;
    const auto cut = key.find_last_of(".[");
    if (cut == std::string::npos) break;
    key.erase(cut);
  }
  return origin.location;
}

double max_abs(const MatX& m) { return m.size() == 0 ? 0.0 : m.cwiseAbs().maxCoeff(); }

double spectral_norm(const MatX& m) {
  return m.size() == 0 ? 0.0 : Eigen::JacobiSVD<MatX>(m).singularValues()(0);
}

// Eigenvalues of the symmetric part, ascending.
VecX symmetric_eigenvalues(const MatX& m) {
  const MatX symmetric = 0.5 * (m + m.transpose());
  return Eigen::SelfAdjointEigenSolver<MatX>(symmetric, Eigen::EigenvaluesOnly).eigenvalues();
}

// The six rigid-body motions of a link as a 12×6 matrix: [u; D·u] over [Δt_from; Δt_to], the
// rotation columns scaled by the length (at least 1 m) so that both kinds of motion weigh alike.
Eigen::Matrix<double, 12, 6> rigid_body_motions(const Vec3& d) {
  Eigen::Matrix<double, 12, 6> R;
  R.topRows<6>() = Mat6::Identity();
  R.bottomRows<6>() = rigid_transport(d);
  R.rightCols<3>() *= std::max(1.0, d.norm());
  return R;
}

struct Kind {
  const char* path;  // "joints"
  const char* noun;  // "joint"
};
constexpr Kind kPoints{"points", "point"};
constexpr Kind kLinks{"links", "link"};
constexpr Kind kJoints{"joints", "joint"};
constexpr Kind kSupports{"supports", "support"};
constexpr Kind kEndEffectors{"end_effectors", "end effector"};

// The entity a diagnostic is about: its key path and where it was written.
struct Subject {
  std::string path;
  const Origin* origin;
};

template <class Entity>
Subject subject_of(const Kind& kind, const Entity& entity, std::size_t index) {
  return {entity.name.empty() ? std::string(kind.path) + "[" + std::to_string(index) + "]"
                              : std::string(kind.path) + "." + entity.name,
          &entity.origin};
}

template <class Entity>
std::vector<std::string> names_of(const std::vector<Entity>& entities) {
  std::vector<std::string> names;
  for (const auto& e : entities) names.push_back(e.name);
  return names;
}

// The diagonal of the box around the model's points.
double extent(const Model& model) {
  std::optional<Eigen::AlignedBox3d> box;
  for (const auto& p : model.points) {
    if (!p.position.allFinite()) continue;
    if (box)
      box->extend(p.position);
    else
      box = Eigen::AlignedBox3d(p.position);
  }
  return box ? box->diagonal().norm() : 0.0;
}

class Checker {
 public:
  explicit Checker(const Model& model)
      : model_(model), index_(model), zero_length_(kLengthTolerance * std::max(1.0, extent(model))) {
    model_origin_.location.file = model.source_file;
  }

  std::vector<Diagnostic> run() {
    check_names(model_.points, kPoints);
    for (std::size_t i = 0; i < model_.points.size(); ++i) check_point(i);
    check_names(model_.links, kLinks);
    if (model_.links.empty())
      report(Subject{"", &model_origin_}, "links", "the model has no links; add at least one link");
    for (std::size_t i = 0; i < model_.links.size(); ++i) check_link(i);
    check_names(model_.joints, kJoints);
    for (std::size_t i = 0; i < model_.joints.size(); ++i) check_joint(i);
    check_names(model_.supports, kSupports);
    for (std::size_t i = 0; i < model_.supports.size(); ++i) check_support(i);
    check_points_partly_named();
    for (std::size_t i = 0; i < model_.loads.size(); ++i) check_load(i);
    check_names(model_.end_effectors, kEndEffectors);
    for (std::size_t i = 0; i < model_.end_effectors.size(); ++i) check_end_effector(i);
    return std::move(found_);
  }

 private:
  void report(const Subject& s, const std::string& key, std::string message) {
    const std::string path = key.empty() ? s.path : s.path.empty() ? key : s.path + "." + key;
    found_.push_back({locate(*s.origin, key), path, std::move(message)});
  }

  // ---- names and references ------------------------------------------------------------

  template <class Entity>
  void check_names(const std::vector<Entity>& entities, const Kind& kind) {
    std::set<std::string> seen;
    for (std::size_t i = 0; i < entities.size(); ++i) {
      const auto& name = entities[i].name;
      if (name.empty())
        report(subject_of(kind, entities[i], i), "",
               std::string("a ") + kind.noun + " needs a non-empty name");
      else if (!seen.insert(name).second)
        report(subject_of(kind, entities[i], i), "",
               std::string("another ") + kind.noun + " is named '" + name +
                   "' too; names must be unique");
    }
  }

  // Suggestions compare a name with every name of its kind; past the first few hundred unknown
  // references (a generated file gone wrong) the messages go on without them, so that
  // validation stays linear in the model's size.
  std::string no_such(const Kind& kind, const std::string& name, const std::vector<std::string>& names) {
    if (name.empty()) return std::string("a ") + kind.noun + " name is needed";
    if (names.empty())
      return std::string("no ") + kind.noun + " named '" + name + "'; the model has no " +
             kind.path;
    if (suggestions_left_ == 0) return std::string("no ") + kind.noun + " named '" + name + "'";
    --suggestions_left_;
    return std::string("no ") + kind.noun + " named '" + name + "'" +
           detail::suggestion(name, names, std::string(kind.path) + " are");
  }

  bool point_exists(const Subject& s, const std::string& key, const std::string& point) {
    if (index_.point(point)) return true;
    report(s, key, no_such(kPoints, point, point_names_));
    return false;
  }

  bool link_exists(const Subject& s, const std::string& key, const std::string& link) {
    if (index_.link(link) >= 0) return true;
    report(s, key, no_such(kLinks, link, link_names_));
    return false;
  }

  // A load or end effector: `{at, link?}` must mean exactly one link end.
  void check_link_end_reference(const Subject& s, const std::string& at,
                                const std::optional<std::string>& link) {
    if (!point_exists(s, "at", at)) return;
    if (link && !link_exists(s, "link", *link)) return;
    std::string problem;
    if (!index_.resolve(at, link, problem))
      report(s, link ? "link" : "at", problem);
  }

  // ---- values ----------------------------------------------------------------------------

  bool require_finite(const Subject& s, const std::string& key, const MatX& values) {
    if (values.allFinite()) return true;
    report(s, key, key + " must hold finite numbers only");
    return false;
  }

  bool require_nonzero_vector(const Subject& s, const std::string& key, const Vec3& v) {
    if (!require_finite(s, key, v)) return false;
    if (v.norm() > 0) return true;
    report(s, key, key + " is a zero vector; give a direction");
    return false;
  }

  bool require_symmetric(const Subject& s, const std::string& key, const MatX& m) {
    Eigen::Index row = 0, col = 0;
    const double asymmetry = (m - m.transpose()).cwiseAbs().maxCoeff(&row, &col);
    if (asymmetry <= kMatrixTolerance * max_abs(m)) return true;
    const auto entry = [&](Eigen::Index i, Eigen::Index j) {
      return key + "[" + std::to_string(i) + "][" + std::to_string(j) +
             "] = " + format_number(m(i, j));
    };
    report(s, key,
           key + " must be symmetric, but " + entry(row, col) + " and " + entry(col, row) +
               " (allowed difference: 1e-9·max|" + key + "|)");
    return false;
  }

  void require_positive_definite(const Subject& s, const std::string& key, const MatX& m) {
    if (!require_finite(s, key, m) || !require_symmetric(s, key, m)) return;
    const VecX eigenvalues = symmetric_eigenvalues(m);
    const double smallest = eigenvalues(0);
    const double largest = eigenvalues.cwiseAbs().maxCoeff();
    if (smallest > kDefiniteTolerance * largest) return;
    report(s, key,
           key + " must be positive definite; its smallest eigenvalue is " +
               format_number(smallest) + " (largest " +
               format_number(eigenvalues(eigenvalues.size() - 1)) + ")");
  }

  // ---- points and links ------------------------------------------------------------------

  void check_point(std::size_t index) {
    const Point& p = model_.points[index];
    const Subject s = subject_of(kPoints, p, index);
    if (!p.position.allFinite()) report(s, "", "the position must hold finite numbers only");
  }

  void check_link(std::size_t index) {
    const Link& link = model_.links[index];
    const Subject s = subject_of(kLinks, link, index);
    const bool from_known = point_exists(s, "from", link.from);
    const bool to_known = point_exists(s, "to", link.to);
    std::optional<Vec3> d;  // from → to, where both points are known and usable
    if (from_known && to_known) {
      const Vec3 span =
          index_.point(link.to)->position - index_.point(link.from)->position;
      if (span.allFinite()) d = span;
    }
    if (const auto* beam = std::get_if<BeamLink>(&link.kind)) {
      require_length(s, d, "a beam");
      check_material(s, beam->material);
      check_section(s, beam->section);
      check_shear(s, *beam);
      check_zref(s, beam->zref, d);
    } else if (const auto* matrix = std::get_if<MatrixLink>(&link.kind)) {
      require_length(s, d, "a matrix link");
      if (matrix->frame == LinkFrame::local) check_zref(s, matrix->zref, d);
      check_stiffness_matrix(s, *matrix, d);
    } else if (const auto* compliance = std::get_if<ComplianceLink>(&link.kind)) {
      if (compliance->frame == LinkFrame::local) {
        require_length(s, d, "a compliance link with frame: local");
        check_zref(s, compliance->zref, d);
      }
      require_positive_definite(s, "C", compliance->C);
    }
  }

  void require_length(const Subject& s, const std::optional<Vec3>& d, const std::string& what) {
    if (!d || d->norm() > zero_length_) return;
    report(s, "",
           "the link has zero length (its points coincide); " + what +
               " needs a length (only rigid links and compliance links with "
               "frame: global may have zero length)");
  }

  void check_material(const Subject& s, const Material& m) {
    for (const auto& defect : detail::material_defects(m))
      report(s, defect.key.empty() ? "material" : "material." + defect.key, defect.message);
  }

  void check_section(const Subject& s, const Section& section) {
    for (const auto& defect : detail::section_defects(section))
      report(s, defect.key.empty() ? "section" : "section." + defect.key, defect.message);
  }

  void check_shear(const Subject& s, const BeamLink& beam) {
    if (!beam.shear) return;
    const SectionProperties p = section_properties(beam.section);
    if (p.Asy && p.Asz) return;
    report(s, "shear",
           "shear: true needs the shear areas Asy and Asz; a generic section must "
           "give both");
  }

  void check_zref(const Subject& s, const std::optional<Vec3>& zref, const std::optional<Vec3>& d) {
    if (!zref || !require_nonzero_vector(s, "zref", *zref)) return;
    if (!d || d->norm() <= zero_length_) return;
    if (zref->normalized().cross(d->normalized()).norm() < kParallelTolerance)
      report(s, "zref",
             "zref is parallel to the link (from → to), so it cannot fix the local "
             "x-z plane; give a direction across the link");
  }

  // Sections.md: symmetric, positive semi-definite and free-free.
  void check_stiffness_matrix(const Subject& s, const MatrixLink& link,
                              const std::optional<Vec3>& d) {
    const MatX K = link.K;
    if (!require_finite(s, "K", K) || !require_symmetric(s, "K", K)) return;
    const double scale = max_abs(K);
    const double smallest = symmetric_eigenvalues(K)(0);
    if (smallest < -kMatrixTolerance * scale)
      report(s, "K",
             "K must be positive semi-definite; its smallest eigenvalue is " +
                 format_number(smallest));
    if (!d) return;
    // A rotation to the local frame preserves the norms, so check where K is given.
    const Vec3 along = link.frame == LinkFrame::local ? Vec3(d->norm(), 0, 0) : *d;
    const MatX R = rigid_body_motions(along);
    const double residual = spectral_norm(K * R);
    const double bound = kFreeFreeTolerance * spectral_norm(K) * spectral_norm(R);
    if (residual > bound)
      report(s, "K",
             "K is not free-free: the link's rigid-body motions are not in its null "
             "space (‖K·R‖₂ = " +
                 format_number(residual) + ", above 1e-6·‖K‖₂·‖R‖₂ = " + format_number(bound) +
                 "); such a matrix would tie the link to the ground");
  }

  // ---- joints and supports ---------------------------------------------------------------

  void check_kinematics(const Subject& s, const Kinematics& k) {
    switch (k.type) {
      case JointType::rigid:
      case JointType::spherical:
        break;
      case JointType::revolute:
      case JointType::prismatic:
      case JointType::cylindrical:
        require_nonzero_vector(s, "axis", k.axis);
        break;
      case JointType::universal: {
        const bool a = require_nonzero_vector(s, "axes[0]", k.axis);
        const bool b = require_nonzero_vector(s, "axes[1]", k.axis_b);
        if (a && b && k.axis.normalized().cross(k.axis_b.normalized()).norm() < kParallelTolerance)
          report(s, "axes", "the two axes of a universal joint must not be parallel");
        break;
      }
      case JointType::planar:
        require_nonzero_vector(s, "normal", k.normal);
        break;
      case JointType::custom:
        check_custom_rows(s, k.free_rows);
        break;
    }
  }

  void check_custom_rows(const Subject& s, const std::vector<Vec6>& rows) {
    if (rows.empty()) {
      report(s, "free", "a custom joint needs at least one free direction in free");
      return;
    }
    if (rows.size() > 6) {
      report(
          s, "free",
          "a custom joint has at most 6 free directions (got " + std::to_string(rows.size()) + ")");
      return;
    }
    bool rows_usable = true;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string key = "free[" + std::to_string(i) + "]";
      if (!require_finite(s, key, rows[i])) {
        rows_usable = false;
      } else if (rows[i].norm() == 0) {
        report(s, key, "row " + std::to_string(i) + " of free is zero; give a direction");
        rows_usable = false;
      }
    }
    if (!rows_usable) return;
    MatX stacked(static_cast<Eigen::Index>(rows.size()), 6);
    for (std::size_t i = 0; i < rows.size(); ++i)
      stacked.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
    const VecX sigma = Eigen::JacobiSVD<MatX>(stacked).singularValues();
    if (sigma(sigma.size() - 1) < kRankTolerance * sigma(0))
      report(s, "free",
             "the rows of free are linearly dependent (smallest singular value " +
                 format_number(sigma(sigma.size() - 1)) + ", largest " + format_number(sigma(0)) +
                 "); give independent directions");
  }

  void check_connection(const Subject& s, const Connection& c, const char* noun) {
    check_kinematics(s, c.kinematics);
    const int p = free_direction_count(c.kinematics);
    const std::string type = to_string(c.kinematics.type);
    if (p == 0 && (c.stiffness || c.preload)) {
      report(s, c.stiffness ? "stiffness" : "preload",
             std::string("a ") + type + " " + noun + " has no free directions, so it takes no " +
                 (c.stiffness ? "stiffness" : "preload"));
      return;
    }
    const std::string sized = " (p = " + std::to_string(p) + " for a " + type + " " + noun + ")";
    if (c.stiffness) {
      if (c.stiffness->rows() != p || c.stiffness->cols() != p)
        report(s, "stiffness",
               "stiffness must be p×p" + sized + "; got " + std::to_string(c.stiffness->rows()) +
                   "×" + std::to_string(c.stiffness->cols()));
      else
        require_positive_definite(s, "stiffness", *c.stiffness);
    }
    if (c.preload) {
      if (c.preload->size() != p)
        report(s, "preload",
               "preload must hold p values" + sized + "; got " + std::to_string(c.preload->size()));
      else
        require_finite(s, "preload", *c.preload);
      if (c.actuated && !c.stiffness)
        report(s, "preload",
               "a preload on a locked actuator (actuated, no stiffness) has no "
               "effect; give the actuator a stiffness or remove the preload");
    }
  }

  // Records that `owner` takes the link end; a second taker is a defect.
  void claim(const Subject& s, const std::string& key, const detail::LinkEndRef& end,
             const std::string& owner) {
    const auto [it, is_new] = end_owner_.emplace(end.id(), owner);
    if (!is_new)
      report(s, key,
             "link end " + end_name(model_, end) + " is already in " + it->second +
                 "; a link end takes part in at most one joint or support");
  }

  void claim_listed_ends(const Subject& s, const std::string& at,
                         const std::vector<std::string>& links, const std::string& owner) {
    std::set<std::string> listed;
    for (std::size_t i = 0; i < links.size(); ++i) {
      const std::string key = "links[" + std::to_string(i) + "]";
      if (!listed.insert(links[i]).second) {
        report(s, key, "link '" + links[i] + "' is listed twice");
        continue;
      }
      if (!link_exists(s, key, links[i])) continue;
      std::string problem;
      if (const auto end = index_.resolve(at, links[i], problem))
        claim(s, key, *end, owner);
      else
        report(s, key, problem);
    }
  }

  void check_joint(std::size_t index) {
    const Joint& joint = model_.joints[index];
    const Subject s = subject_of(kJoints, joint, index);
    check_connection(s, joint.connection, "joint");
    const Connection& c = joint.connection;
    const auto count = std::to_string(joint.links.size());
    if (joint.links.size() < 2)
      report(s, "links", "a joint connects at least two link ends (got " + count + ")");
    else if ((c.stiffness || c.preload) && joint.links.size() != 2)
      report(s, "links",
             "an elastic or preloaded joint connects exactly two link ends (got " + count + ")");
    if (point_exists(s, "at", joint.at))
      claim_listed_ends(s, joint.at, joint.links, "joint '" + joint.name + "'");
  }

  void check_support(std::size_t index) {
    const Support& support = model_.supports[index];
    const Subject s = subject_of(kSupports, support, index);
    check_connection(s, support.connection, "support");
    if (!point_exists(s, "at", support.at)) return;
    const std::string owner = "support '" + support.name + "'";
    if (!support.links.empty()) {
      claim_listed_ends(s, support.at, support.links, owner);
      return;
    }
    const auto ends = index_.ends_at(support.at);
    if (ends.empty()) report(s, "at", "no link end is at point '" + support.at + "'");
    for (const auto& end : ends) claim(s, "at", end, owner);
  }

  // Model-format.md: ends that no joint names are welded together, so beside a joint that
  // names some ends of a point, an unnamed end would be welded to whichever the user did not
  // mean; the user must say which.
  void check_points_partly_named() {
    for (std::size_t i = 0; i < model_.points.size(); ++i) {
      const Point& point = model_.points[i];
      std::vector<std::string> unnamed;
      bool some_named = false;
      for (const auto& end : index_.ends_at(point.name)) {
        if (end_owner_.count(end.id()))
          some_named = true;
        else
          unnamed.push_back(end_name(model_, end));
      }
      if (some_named && !unnamed.empty())
        report(subject_of(kPoints, point, i), "",
               "at point '" + point.name + "' the link ends " + detail::comma_list(unnamed) +
                   " are in no joint or support, while other link ends there are; add them to "
                   "a joint or support");
    }
  }

  // ---- loads and end effectors -----------------------------------------------------------

  void check_load(std::size_t index) {
    const Load& load = model_.loads[index];
    const Subject s{"loads[" + std::to_string(index) + "]", &load.origin};
    check_link_end_reference(s, load.at, load.link);
    require_finite(s, "wrench", load.wrench);
  }

  void check_end_effector(std::size_t index) {
    const EndEffector& ee = model_.end_effectors[index];
    check_link_end_reference(subject_of(kEndEffectors, ee, index), ee.at, ee.link);
  }

  const Model& model_;
  const detail::ModelIndex index_;
  int suggestions_left_ = 200;
  const std::vector<std::string> point_names_ = names_of(model_.points);
  const std::vector<std::string> link_names_ = names_of(model_.links);
  double zero_length_;
  Origin model_origin_;  // for defects of the model as a whole
  std::vector<Diagnostic> found_;
  std::map<int, std::string> end_owner_;  // link end id → "joint 'J1'"
};

}  // namespace

namespace detail {

namespace {
void require_positive(std::vector<ValueDefect>& defects, const std::string& key, double value) {
  if (!(value > 0 && std::isfinite(value)))
    defects.push_back({key, key + " must be a positive number (got " + format_number(value) + ")"});
}
}  // namespace

std::vector<ValueDefect> material_defects(const Material& m) {
  std::vector<ValueDefect> defects;
  require_positive(defects, "E", m.E);
  if (m.nu && m.G)
    defects.push_back({"", "give exactly one of nu or G with E, not both"});
  else if (!m.nu && !m.G)
    defects.push_back({"", "give exactly one of nu or G with E; neither is given"});
  else if (m.G)
    require_positive(defects, "G", *m.G);
  else if (!(*m.nu > -1 && *m.nu < 0.5))
    defects.push_back({"nu", "nu must lie in (-1, 0.5) (got " + format_number(*m.nu) + ")"});
  return defects;
}

std::vector<ValueDefect> section_defects(const Section& s) {
  std::vector<ValueDefect> defects;
  for (const auto& dimension : section_dimensions(s.shape))
    require_positive(defects, dimension.key, s.*dimension.value);
  if (s.Asy) require_positive(defects, "Asy", *s.Asy);
  if (s.Asz) require_positive(defects, "Asz", *s.Asz);
  const auto thin_wall = [&](double outer, const char* outer_name) {
    if (s.t > 0 && outer > 0 && !(s.t < outer / 2))
      defects.push_back({"t", "wall thickness t = " + format_number(s.t) + " must be less than " +
                                  outer_name + "/2 = " + format_number(outer / 2)});
  };
  if (s.shape == SectionShape::tube) thin_wall(s.D, "D");
  if (s.shape == SectionShape::rect_tube) thin_wall(std::min(s.b, s.h), "min(b, h)");
  return defects;
}

}  // namespace detail

std::vector<Diagnostic> find_defects(const Model& model) { return Checker(model).run(); }

void validate(const Model& model) {
  auto defects = find_defects(model);
  if (!defects.empty()) throw InputError(std::move(defects));
}

}  // namespace stiffmsa
