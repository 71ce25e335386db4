// Every defect that can be found on a Model without solving it, whether the model came from a
// file or from the C++ API (model-format.md, sections.md). Key paths name the user's entities;
// locations come from the entities' Origin, so file models point at the line.
#include "stiffmsa/validate.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "model/link_ends.hpp"
#include "model/suggest.hpp"
#include "model/value_checks.hpp"
#include "stiffmsa/number_text.hpp"
#include "tolerances.hpp"

namespace stiffmsa {
namespace {

using detail::kDefiniteTolerance;
using detail::kFreeFreeTolerance;
using detail::kLengthTolerance;
using detail::kMatrixTolerance;
using detail::kParallelTolerance;
using detail::kRankTolerance;

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
    if (const KeyLocation* found = origin.find(key); found != nullptr)
      return {origin.location.file, found->line, found->column};
    const auto cut = key.find_last_of(".[");
    if (cut == std::string::npos) break;
    key.erase(cut);
  }
  return origin.location;
}

template <class Derived>
double max_abs(const Eigen::MatrixBase<Derived>& m) {
  return m.size() == 0 ? 0.0 : m.cwiseAbs().maxCoeff();
}

double spectral_norm(const MatX& m) {
  return m.size() == 0 ? 0.0 : Eigen::JacobiSVD<MatX>(m).singularValues()(0);
}

// The extreme eigenvalues of the symmetric part.
struct Spectrum {
  double smallest = 0;
  double largest = 0;
  double largest_magnitude = 0;
};

template <class Derived>
Spectrum symmetric_spectrum(const Eigen::MatrixBase<Derived>& m) {
  // The stiffness of a revolute or prismatic joint is 1×1: the eigensolver would return the
  // one entry of the symmetric part as it is, so take it without the solver's heap work.
  if (m.rows() == 1 && m.cols() == 1) {
    const double only = 0.5 * (m(0, 0) + m(0, 0));
    return {only, only, std::abs(only)};
  }
  const MatX symmetric = 0.5 * (m + m.transpose());
  const VecX eigenvalues =
      Eigen::SelfAdjointEigenSolver<MatX>(symmetric, Eigen::EigenvaluesOnly).eigenvalues();
  return {eigenvalues(0), eigenvalues(eigenvalues.size() - 1), eigenvalues.cwiseAbs().maxCoeff()};
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
constexpr Kind kLoadCases{"load_cases", "load case"};

// A settlement's component along a free direction of its support counts as zero below this
// fraction of the settlement's translation (or rotation) part: rounding of a tilted axis.
constexpr double kSettlementFreeTolerance = 1e-9;

// The entity a diagnostic is about: where it was written and its key path ("links.arm", or
// "links[3]" where it has no name), spelt out only when there is a defect to report.
struct Subject {
  const char* collection;   // "links"; nullptr for the model as a whole (path "")
  const std::string* name;  // nullptr: the entity goes by its position
  std::size_t position;
  const Origin* origin;

  std::string path() const {
    if (!collection) return "";
    if (name) return std::string(collection) + "." + *name;
    return std::string(collection) + "[" + std::to_string(position) + "]";
  }
};

template <class Entity>
Subject subject_of(const Kind& kind, const Entity& entity, std::size_t index) {
  return {kind.path, entity.name.empty() ? nullptr : &entity.name, index, &entity.origin};
}

// A key within an entity ("axis", "free[2]"), spelt out only for a report.
struct Key {
  Key(const char* name) : name(name) {}  // NOLINT(google-explicit-constructor): keys are literals
  Key(const char* name, std::size_t position) : name(name), position(position) {}
  std::string str() const {
    return position ? std::string(name) + "[" + std::to_string(*position) + "]" : std::string(name);
  }
  const char* name;
  std::optional<std::size_t> position;
};

// Who holds a link end, for the message when a second taker claims it.
struct Owner {
  const char* noun = nullptr;  // "joint", "support"; nullptr while nobody holds the end
  const std::string* name = nullptr;
  std::string str() const { return std::string(noun) + " '" + *name + "'"; }
};

template <class Entity>
std::vector<std::string> names_of(const std::vector<Entity>& entities) {
  std::vector<std::string> names;
  names.reserve(entities.size());
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

// Whether the i-th of `count` names repeats an earlier one. Joints list a few links and
// models have a few joints, where a scan is cheaper than building a table; long lists get one.
template <class NameOf>
class RepeatFinder {
 public:
  RepeatFinder(std::size_t count, NameOf name_of) : name_of_(std::move(name_of)) {
    if (count <= kScanLimit) return;
    table_.emplace(count);
    for (std::size_t i = 0; i < count; ++i) table_->add(name_of_(i));
  }

  bool operator()(std::size_t i) const {
    const std::string_view name = name_of_(i);
    if (table_) return table_->find(name) != static_cast<int>(i);
    for (std::size_t earlier = 0; earlier < i; ++earlier)
      if (name_of_(earlier) == name) return true;
    return false;
  }

 private:
  static constexpr std::size_t kScanLimit = 16;
  NameOf name_of_;
  std::optional<detail::NameTable> table_;
};

class Checker {
 public:
  Checker(const Model& model, const detail::ModelIndex& index)
      : model_(model),
        index_(index),
        zero_length_(kLengthTolerance * std::max(1.0, extent(model))),
        end_owner_(2 * model.links.size()) {
    model_origin_.location.file = model.source_file;
  }

  std::vector<Diagnostic> run() {
    check_names(model_.points, kPoints, [&](std::size_t i) {
      return index_.names_repeat() &&
             index_.point_position(model_.points[i].name) != static_cast<int>(i);
    });
    for (std::size_t i = 0; i < model_.points.size(); ++i) check_point(i);
    check_names(model_.links, kLinks, [&](std::size_t i) {
      return index_.names_repeat() && index_.link(model_.links[i].name) != static_cast<int>(i);
    });
    if (model_.links.empty())
      report(Subject{nullptr, nullptr, 0, &model_origin_}, "links",
             "the model has no links; add at least one link");
    for (std::size_t i = 0; i < model_.links.size(); ++i) check_link(i);
    check_names(model_.joints, kJoints);
    for (std::size_t i = 0; i < model_.joints.size(); ++i) check_joint(i);
    check_names(model_.supports, kSupports);
    for (std::size_t i = 0; i < model_.supports.size(); ++i) check_support(i);
    check_points_partly_named();
    for (std::size_t i = 0; i < model_.loads.size(); ++i) check_load(i);
    check_link_loads(model_.link_loads, "link_loads");
    check_gravity(model_.gravity, Subject{nullptr, nullptr, 0, &model_origin_}, "gravity");
    check_names(model_.load_cases, kLoadCases);
    for (std::size_t i = 0; i < model_.load_cases.size(); ++i) check_load_case(i);
    check_analysis();
    check_names(model_.end_effectors, kEndEffectors);
    for (std::size_t i = 0; i < model_.end_effectors.size(); ++i) check_end_effector(i);
    return std::move(found_);
  }

  // The checks of values alone, for a model whose structure (names, references, connectivity,
  // sizes) was validated: what a new pose of a Structure needs.
  std::vector<Diagnostic> run_value_checks() {
    for (std::size_t i = 0; i < model_.points.size(); ++i) check_point(i);
    for (std::size_t i = 0; i < model_.links.size(); ++i) check_link(i);
    for (std::size_t i = 0; i < model_.joints.size(); ++i)
      check_connection_values(subject_of(kJoints, model_.joints[i], i),
                              model_.joints[i].connection);
    for (std::size_t i = 0; i < model_.supports.size(); ++i) {
      const Subject s = subject_of(kSupports, model_.supports[i], i);
      check_connection_values(s, model_.supports[i].connection);
      check_settlement(s, model_.supports[i]);
    }
    for (std::size_t i = 0; i < model_.loads.size(); ++i)
      require_finite(Subject{"loads", nullptr, i, &model_.loads[i].origin}, "wrench",
                     model_.loads[i].wrench);
    check_link_load_values(model_.link_loads, "link_loads");
    if (model_.gravity)
      require_finite(Subject{nullptr, nullptr, 0, &model_origin_}, "gravity", *model_.gravity);
    for (const LoadCase& load_case : model_.load_cases) {
      const std::string prefix = "load_cases." + load_case.name + ".";
      const std::string loads = prefix + "loads";
      for (std::size_t i = 0; i < load_case.loads.size(); ++i)
        require_finite(Subject{loads.c_str(), nullptr, i, &load_case.loads[i].origin}, "wrench",
                       load_case.loads[i].wrench);
      check_link_load_values(load_case.link_loads, prefix + "link_loads");
      if (load_case.gravity)
        require_finite(Subject{kLoadCases.path, &load_case.name, 0, &load_case.origin}, "gravity",
                       *load_case.gravity);
    }
    return std::move(found_);
  }

 private:
  void report(const Subject& s, const std::string& key, std::string message) {
    const std::string subject_path = s.path();
    const std::string path = key.empty()            ? subject_path
                             : subject_path.empty() ? key
                                                    : subject_path + "." + key;
    found_.push_back({locate(*s.origin, key), path, std::move(message)});
  }

  // ---- names and references ------------------------------------------------------------

  // `repeats(i)`: whether an entity before entities[i] has its name.
  template <class Entity, class Repeats>
  void check_names(const std::vector<Entity>& entities, const Kind& kind, const Repeats& repeats) {
    for (std::size_t i = 0; i < entities.size(); ++i) {
      const auto& name = entities[i].name;
      if (name.empty())
        report(subject_of(kind, entities[i], i), "",
               std::string("a ") + kind.noun + " needs a non-empty name");
      else if (repeats(i))
        report(subject_of(kind, entities[i], i), "",
               std::string("another ") + kind.noun + " is named '" + name +
                   "' too; names must be unique");
    }
  }

  template <class Entity>
  void check_names(const std::vector<Entity>& entities, const Kind& kind) {
    check_names(entities, kind,
                RepeatFinder(entities.size(),
                             [&](std::size_t i) -> std::string_view { return entities[i].name; }));
  }

  // Suggestions compare a name with every name of its kind; past the first few hundred unknown
  // references (a generated file gone wrong) the messages go on without them, so that
  // validation stays linear in the model's size.
  std::string no_such(const Kind& kind, const std::string& name,
                      const std::vector<std::string>& names) {
    if (name.empty()) return std::string("a ") + kind.noun + " name is needed";
    if (names.empty())
      return std::string("no ") + kind.noun + " named '" + name + "'; the model has no " +
             kind.path;
    if (suggestions_left_ == 0) return std::string("no ") + kind.noun + " named '" + name + "'";
    --suggestions_left_;
    return std::string("no ") + kind.noun + " named '" + name + "'" +
           detail::suggestion(name, names, std::string(kind.path) + " are");
  }

  bool point_exists(const Subject& s, const Key& key, const std::string& point) {
    return index_.point(point) || report_no_point(s, key, point);
  }

  // For a link's ends, whose points the index has looked up already.
  bool point_exists(const Subject& s, const Key& key, int end_id, const std::string& point) {
    return index_.point_of_end(end_id) >= 0 || report_no_point(s, key, point);
  }

  bool report_no_point(const Subject& s, const Key& key, const std::string& point) {
    if (!point_names_) point_names_ = names_of(model_.points);
    report(s, key.str(), no_such(kPoints, point, *point_names_));
    return false;
  }

  bool link_exists(const Subject& s, const Key& key, const std::string& link) {
    if (index_.link(link) >= 0) return true;
    if (!link_names_) link_names_ = names_of(model_.links);
    report(s, key.str(), no_such(kLinks, link, *link_names_));
    return false;
  }

  // A load or end effector: `{at, link?}` must mean exactly one link end.
  void check_link_end_reference(const Subject& s, const std::string& at,
                                const std::optional<std::string>& link) {
    if (!point_exists(s, "at", at)) return;
    if (link && !link_exists(s, "link", *link)) return;
    std::string problem;
    if (!index_.resolve(at, link, problem)) report(s, link ? "link" : "at", problem);
  }

  // ---- values ----------------------------------------------------------------------------

  template <class Derived>
  bool require_finite(const Subject& s, const Key& key, const Eigen::MatrixBase<Derived>& values) {
    if (values.allFinite()) return true;
    report(s, key.str(), key.str() + " must hold finite numbers only");
    return false;
  }

  bool require_nonzero_vector(const Subject& s, const Key& key, const Vec3& v) {
    if (!require_finite(s, key, v)) return false;
    if (v.norm() > 0) return true;
    report(s, key.str(), key.str() + " is a zero vector; give a direction");
    return false;
  }

  template <class Derived>
  bool require_symmetric(const Subject& s, const Key& key, const Eigen::MatrixBase<Derived>& m) {
    // The first largest |m(i, j) − m(j, i)| in column-major order, as maxCoeff of the
    // difference would find it, without the difference's temporary.
    Eigen::Index row = 0, col = 0;
    double asymmetry = -1;
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i)
        if (const double difference = std::abs(m(i, j) - m(j, i)); difference > asymmetry) {
          asymmetry = difference;
          row = i;
          col = j;
        }
    if (asymmetry <= kMatrixTolerance * max_abs(m)) return true;
    const std::string name = key.str();
    const auto entry = [&](Eigen::Index i, Eigen::Index j) {
      return name + "[" + std::to_string(i) + "][" + std::to_string(j) +
             "] = " + format_number(m(i, j));
    };
    report(s, name,
           name + " must be symmetric, but " + entry(row, col) + " and " + entry(col, row) +
               " (allowed difference: " + shortest_text(kMatrixTolerance) + "·max|" + name + "|)");
    return false;
  }

  template <class Derived>
  void require_positive_definite(const Subject& s, const Key& key,
                                 const Eigen::MatrixBase<Derived>& m) {
    if (!require_finite(s, key, m) || !require_symmetric(s, key, m)) return;
    const Spectrum spectrum = symmetric_spectrum(m);
    if (spectrum.smallest > kDefiniteTolerance * spectrum.largest_magnitude) return;
    report(s, key.str(),
           key.str() + " must be positive definite; its smallest eigenvalue is " +
               format_number(spectrum.smallest) + " (largest " + format_number(spectrum.largest) +
               ")");
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
    const int from_end = 2 * static_cast<int>(index), to_end = from_end + 1;
    const bool from_known = point_exists(s, "from", from_end, link.from);
    const bool to_known = point_exists(s, "to", to_end, link.to);
    std::optional<Vec3> d;  // from → to, where both points are known and usable
    if (from_known && to_known) {
      const auto position = [&](int end) {
        return model_.points[static_cast<std::size_t>(index_.point_of_end(end))].position;
      };
      const Vec3 span = position(to_end) - position(from_end);
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

  void require_length(const Subject& s, const std::optional<Vec3>& d, const char* what) {
    if (!d || d->norm() > zero_length_) return;
    report(s, "",
           std::string("the link has zero length (its points coincide); ") + what +
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
    const double smallest = symmetric_spectrum(K).smallest;
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
                 format_number(residual) + ", above " + shortest_text(kFreeFreeTolerance) +
                 "·‖K‖₂·‖R‖₂ = " + format_number(bound) +
                 "); such a matrix would tie the link to the ground");
  }

  // ---- joints and supports ---------------------------------------------------------------

  void check_kinematics(const Subject& s, const Kinematics& k) {
    switch (k.type) {
      case JointType::rigid:
      case JointType::spherical: break;
      case JointType::revolute:
      case JointType::prismatic:
      case JointType::cylindrical: require_nonzero_vector(s, "axis", k.axis); break;
      case JointType::universal: {
        const bool a = require_nonzero_vector(s, "axes[0]", k.axis);
        const bool b = require_nonzero_vector(s, "axes[1]", k.axis_b);
        if (a && b && k.axis.normalized().cross(k.axis_b.normalized()).norm() < kParallelTolerance)
          report(s, "axes", "the two axes of a universal joint must not be parallel");
        break;
      }
      case JointType::planar: require_nonzero_vector(s, "normal", k.normal); break;
      case JointType::custom: check_custom_rows(s, k.free_rows); break;
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
      const Key key("free", i);
      if (!require_finite(s, key, rows[i])) {
        rows_usable = false;
      } else if (rows[i].norm() == 0) {
        report(s, key.str(), "row " + std::to_string(i) + " of free is zero; give a direction");
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
    const char* type = to_string(c.kinematics.type);
    if (p == 0 && (c.stiffness || c.preload)) {
      report(s, c.stiffness ? "stiffness" : "preload",
             std::string("a ") + type + " " + noun + " has no free directions, so it takes no " +
                 (c.stiffness ? "stiffness" : "preload"));
      return;
    }
    const auto sized = [&] {
      return " (p = " + std::to_string(p) + " for a " + type + " " + noun + ")";
    };
    if (c.stiffness) {
      if (c.stiffness->rows() != p || c.stiffness->cols() != p)
        report(s, "stiffness",
               "stiffness must be p×p" + sized() + "; got " + std::to_string(c.stiffness->rows()) +
                   "×" + std::to_string(c.stiffness->cols()));
      else
        require_positive_definite(s, "stiffness", *c.stiffness);
    }
    if (c.preload) {
      if (c.preload->size() != p)
        report(
            s, "preload",
            "preload must hold p values" + sized() + "; got " + std::to_string(c.preload->size()));
      else
        require_finite(s, "preload", *c.preload);
      if (c.is_actuated && !c.stiffness)
        report(s, "preload",
               "a preload on a locked actuator (actuated, no stiffness) has no "
               "effect; give the actuator a stiffness or remove the preload");
    }
  }

  // check_connection's checks of values, the sizes being known right.
  void check_connection_values(const Subject& s, const Connection& c) {
    check_kinematics(s, c.kinematics);
    if (c.stiffness) require_positive_definite(s, "stiffness", *c.stiffness);
    if (c.preload) require_finite(s, "preload", *c.preload);
  }

  // Records that `owner` takes the link end; a second taker is a defect.
  void claim(const Subject& s, const Key& key, const detail::LinkEndRef& end, const Owner& owner) {
    Owner& holder = end_owner_[static_cast<std::size_t>(end.id())];
    if (!holder.noun) {
      holder = owner;
      return;
    }
    report(s, key.str(),
           "link end " + end_name(model_, end) + " is already in " + holder.str() +
               "; a link end takes part in at most one joint or support");
  }

  void claim_listed_ends(const Subject& s, const std::string& at,
                         const std::vector<std::string>& links, const Owner& owner) {
    const RepeatFinder repeats(links.size(),
                               [&](std::size_t i) -> std::string_view { return links[i]; });
    for (std::size_t i = 0; i < links.size(); ++i) {
      const Key key("links", i);
      if (repeats(i)) {
        report(s, key.str(), "link '" + links[i] + "' is listed twice");
        continue;
      }
      if (!link_exists(s, key, links[i])) continue;
      std::string problem;
      if (const auto end = index_.resolve(at, links[i], problem))
        claim(s, key, *end, owner);
      else
        report(s, key.str(), problem);
    }
  }

  void check_joint(std::size_t index) {
    const Joint& joint = model_.joints[index];
    const Subject s = subject_of(kJoints, joint, index);
    check_connection(s, joint.connection, "joint");
    const Connection& c = joint.connection;
    const auto count = [&] { return std::to_string(joint.links.size()); };
    if (joint.links.size() < 2)
      report(s, "links", "a joint connects at least two link ends (got " + count() + ")");
    else if ((c.stiffness || c.preload) && joint.links.size() != 2)
      report(s, "links",
             "an elastic or preloaded joint connects exactly two link ends (got " + count() + ")");
    if (point_exists(s, "at", joint.at))
      claim_listed_ends(s, joint.at, joint.links, Owner{"joint", &joint.name});
  }

  void check_support(std::size_t index) {
    const Support& support = model_.supports[index];
    const Subject s = subject_of(kSupports, support, index);
    check_connection(s, support.connection, "support");
    check_settlement(s, support);
    if (!point_exists(s, "at", support.at)) return;
    const Owner owner{"support", &support.name};
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
      // With every name once, point i is the one its name finds.
      const auto ends =
          index_.names_repeat() ? index_.ends_at(point.name) : index_.ends_at(static_cast<int>(i));
      const auto named = [&](const detail::LinkEndRef& end) {
        return end_owner_[static_cast<std::size_t>(end.id())].noun != nullptr;
      };
      const bool some_named = std::any_of(ends.begin(), ends.end(), named);
      if (!some_named || std::all_of(ends.begin(), ends.end(), named)) continue;
      std::vector<std::string> unnamed;
      for (const auto& end : ends)
        if (!named(end)) unnamed.push_back(end_name(model_, end));
      report(subject_of(kPoints, point, i), "",
             "at point '" + point.name + "' the link ends " + detail::comma_list(unnamed) +
                 " are in no joint or support, while other link ends there are; add them to "
                 "a joint or support");
    }
  }

  // ---- loads and end effectors -----------------------------------------------------------

  void check_load(std::size_t index) {
    const Load& load = model_.loads[index];
    const Subject s{"loads", nullptr, index, &load.origin};
    check_link_end_reference(s, load.at, load.link);
    require_finite(s, "wrench", load.wrench);
  }

  // A settlement: finite, and nothing along the directions the support leaves free (there the
  // support holds nothing that could move the structure).
  void check_settlement(const Subject& s, const Support& support) {
    if (!support.displacement || !require_finite(s, "displacement", *support.displacement)) return;
    const Vec6& d = *support.displacement;
    const Kinematics& k = support.connection.kinematics;
    const Vec3 move = d.head<3>(), turn = d.tail<3>();
    // Each free direction of the support, with the settlement's component along it.
    struct Along {
      std::string direction;
      double component;
      double scale;  // of the part of the settlement it is compared with
    };
    std::vector<Along> free;
    const auto unit = [](const Vec3& v) { return v.norm() > 0 ? Vec3(v.normalized()) : v; };
    const auto axis_text = [](const Vec3& v) {
      return "[" + format_number(v.x()) + ", " + format_number(v.y()) + ", " +
             format_number(v.z()) + "]";
    };
    const auto rotation_about = [&](const std::string& name, const Vec3& axis) {
      free.push_back(
          {"rotation about " + name + " " + axis_text(axis), unit(axis).dot(turn), turn.norm()});
    };
    const auto translation_along = [&](const std::string& name, const Vec3& axis) {
      free.push_back(
          {"translation along " + name + " " + axis_text(axis), unit(axis).dot(move), move.norm()});
    };
    static constexpr const char* kComponents[] = {"dx", "dy", "dz", "rx", "ry", "rz"};
    switch (k.type) {
      case JointType::rigid: break;
      case JointType::revolute: rotation_about("its axis", k.axis); break;
      case JointType::prismatic: translation_along("its axis", k.axis); break;
      case JointType::cylindrical:
        rotation_about("its axis", k.axis);
        translation_along("its axis", k.axis);
        break;
      case JointType::universal:
        rotation_about("axes[0]", k.axis);
        rotation_about("axes[1]", k.axis_b);
        break;
      case JointType::spherical:
        for (int i = 3; i < 6; ++i) free.push_back({kComponents[i], d(i), turn.norm()});
        break;
      case JointType::planar: {
        const Vec3 n = unit(k.normal);
        free.push_back({"translation in its plane (normal " + axis_text(k.normal) + ")",
                        (move - move.dot(n) * n).norm(), move.norm()});
        rotation_about("its normal", k.normal);
        break;
      }
      case JointType::custom:
        for (std::size_t i = 0; i < k.free_rows.size(); ++i) {
          const Vec6& row = k.free_rows[i];
          if (!(row.norm() > 0) || !row.allFinite()) continue;
          free.push_back({"free[" + std::to_string(i) + "]", row.normalized().dot(d), d.norm()});
        }
        break;
    }
    for (const Along& along : free)
      if (std::abs(along.component) > kSettlementFreeTolerance * along.scale) {
        report(s, "displacement",
               "support '" + support.name + "' leaves the " + along.direction +
                   " free, and the settlement moves it that way by " +
                   format_number(along.component) +
                   "; a settlement prescribes only what the support holds: make that "
                   "component zero");
        return;
      }
  }

  bool has_density() const {
    return std::any_of(model_.links.begin(), model_.links.end(), [](const Link& link) {
      const auto* beam = std::get_if<BeamLink>(&link.kind);
      return beam && beam->material.density.has_value();
    });
  }

  // Gravity weighs the beams whose material has a density. With none, the user's gravity would
  // be silently ignored, so it is an error (docs/model-format.md, "gravity").
  void check_gravity(const std::optional<Vec3>& gravity, const Subject& s, const char* key) {
    if (!gravity || !require_finite(s, key, *gravity)) return;
    if (!has_density())
      report(s, key,
             "gravity is given but no beam's material has a density: nothing weighs; give the "
             "materials of the beams that weigh a density (kg/m³), or leave gravity out");
  }

  void check_load_case(std::size_t index) {
    const LoadCase& load_case = model_.load_cases[index];
    const std::string loads = "load_cases." + load_case.name + ".loads";
    for (std::size_t i = 0; i < load_case.loads.size(); ++i) {
      const Load& load = load_case.loads[i];
      const Subject s{loads.c_str(), nullptr, i, &load.origin};
      check_link_end_reference(s, load.at, load.link);
      require_finite(s, "wrench", load.wrench);
    }
    check_link_loads(load_case.link_loads, "load_cases." + load_case.name + ".link_loads");
    check_gravity(load_case.gravity, subject_of(kLoadCases, load_case, index), "gravity");
  }

  // A load along a link: on a link that exists and is not a CAD link, at a position on it.
  void check_link_loads(const std::vector<LinkLoad>& link_loads, const std::string& collection) {
    for (std::size_t i = 0; i < link_loads.size(); ++i) {
      const LinkLoad& load = link_loads[i];
      const Subject s{collection.c_str(), nullptr, i, &load.origin};
      if (link_exists(s, "link", load.link)) {
        const Link& link = model_.links[static_cast<std::size_t>(index_.link(load.link))];
        if (std::holds_alternative<MatrixLink>(link.kind) ||
            std::holds_alternative<ComplianceLink>(link.kind))
          report(s, "link",
                 "link '" + load.link + "' is a " +
                     (std::holds_alternative<MatrixLink>(link.kind) ? "matrix" : "compliance") +
                     " link (from CAD), whose stiffness says nothing of what lies between its "
                     "ends; give a load along it as loads at the link's ends (`{at: " +
                     link.from + ", link: " + link.name + ", wrench: [...]}`)");
      }
    }
    check_link_load_values(link_loads, collection);
  }

  void check_link_load_values(const std::vector<LinkLoad>& link_loads,
                              const std::string& collection) {
    for (std::size_t i = 0; i < link_loads.size(); ++i) {
      const LinkLoad& load = link_loads[i];
      const Subject s{collection.c_str(), nullptr, i, &load.origin};
      if (const auto* distributed = std::get_if<DistributedLinkLoad>(&load.load)) {
        require_finite(s, "distributed.from", distributed->from);
        require_finite(s, "distributed.to", distributed->to);
      } else if (const auto* point = std::get_if<PointLinkLoad>(&load.load)) {
        require_finite(s, "force", point->force);
        require_finite(s, "moment", point->moment);
        if (!(point->position >= 0 && point->position <= 1))
          report(s, "position",
                 "position is a fraction of the link's length from its from end, in [0, 1] "
                 "(got " +
                     format_number(point->position) + ")");
      }
    }
  }

  void check_analysis() {
    const auto& steps = model_.options.load_steps;
    if (steps && *steps <= 0)
      report(Subject{nullptr, nullptr, 0, &model_origin_}, "analysis.load_steps",
             "load_steps must be a positive number of load steps (got " + std::to_string(*steps) +
                 ")");
  }

  void check_end_effector(std::size_t index) {
    const EndEffector& ee = model_.end_effectors[index];
    check_link_end_reference(subject_of(kEndEffectors, ee, index), ee.at, ee.link);
  }

  const Model& model_;
  const detail::ModelIndex& index_;
  int suggestions_left_ = 200;
  // For suggestions; gathered at the first unknown name.
  std::optional<std::vector<std::string>> point_names_, link_names_;
  double zero_length_;
  Origin model_origin_;  // for defects of the model as a whole
  std::vector<Diagnostic> found_;
  std::vector<Owner> end_owner_;  // per link end id
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
  if (m.density) require_positive(defects, "density", *m.density);
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

std::vector<Diagnostic> find_defects(const Model& model) {
  const detail::ModelIndex index(model);
  return Checker(model, index).run();
}

namespace {

// Plausibility (docs/model-format.md, "Plausibility warnings"): values a model may mean, but
// that more often are a slip of units. The moduli of engineering materials run from stiff
// polymers (about 1e9 Pa) to diamond (1.2e12 Pa); a modulus typed in MPa or N/mm² is 1e6 too
// small.
constexpr double kLowestPlausibleModulus = 1e8;    // Pa
constexpr double kHighestPlausibleModulus = 1e12;  // Pa
// Engineering solids weigh from stiff foams (about 50 kg/m³) to tungsten alloys and osmium
// (under 25 000 kg/m³); a density typed in g/cm³ or t/m³ is 1000 times too small.
constexpr double kLowestPlausibleDensity = 50;      // kg/m³
constexpr double kHighestPlausibleDensity = 25000;  // kg/m³
// Robots and machine frames measure metres, frames of buildings tens of them; a model hundreds
// of "metres" across is more likely drawn in millimetres.
constexpr double kLargestPlausibleModelSize = 100;  // m
// Beams of robots and machines are centimetres to decimetres across, a building's girders about
// a metre. A section both wider than this and as wide as its link is long suggests
// millimetres; either alone is a short piece of a finely divided beam, or a large structure.
constexpr double kLargestPlausibleSectionSize = 1;  // m

// Where several links share an implausible value (a named material, say), one warning names
// the first and counts the others.
struct Finding {
  std::string key_path;  // of the first link that has it
  SourceLocation location;
  std::string message;
  std::size_t others = 0;
};

void add_finding(std::vector<Finding>& findings, const Link& link, const std::string& key,
                 std::string message) {
  for (Finding& f : findings)
    if (f.message == message) {
      ++f.others;
      return;
    }
  findings.push_back(
      {"links." + link.name + "." + key, locate(link.origin, key), std::move(message), 0});
}

void check_modulus(std::vector<Finding>& findings, const Link& link, const char* key,
                   double value) {
  if (value >= kLowestPlausibleModulus && value <= kHighestPlausibleModulus) return;
  const bool low = value < kLowestPlausibleModulus;
  add_finding(findings, link, std::string("material.") + key,
              std::string(key) + " = " + shortest_text(value) + " Pa is " +
                  (low ? "below" : "above") +
                  " the moduli of engineering materials (1e8 to 1e12 Pa): " +
                  (low ? "was it given in MPa or N/mm²? " : "was it given in another unit? ") +
                  "stiffmsa reads pascals (steel: E = 2.1e11 Pa)");
}

void check_density(std::vector<Finding>& findings, const Link& link, double density) {
  if (density >= kLowestPlausibleDensity && density <= kHighestPlausibleDensity) return;
  const bool low = density < kLowestPlausibleDensity;
  add_finding(findings, link, "material.density",
              "density = " + shortest_text(density) + " kg/m³ is " + (low ? "below" : "above") +
                  " the densities of engineering materials (50 to 25000 kg/m³): " +
                  (low ? "was it given in g/cm³ or t/m³? " : "was it given in another unit? ") +
                  "stiffmsa reads kg/m³ (steel: density = 7850)");
}

// A beam is slender: a section metres wide and as wide as its link is long was likely given in
// millimetres.
void check_section_size(std::vector<Finding>& findings, const Link& link, const Section& section,
                        double length) {
  if (!(length > 0)) return;
  for (const auto& dimension : detail::section_dimensions(section.shape)) {
    const std::string key = dimension.key;
    const double value = section.*dimension.value;
    // The outer sizes of a shape, or the side of a generic section's area.
    const bool outer = key == "D" || key == "b" || key == "h";
    const double width = outer ? value : key == "A" ? std::sqrt(value) : 0.0;
    if (width > kLargestPlausibleSectionSize && width >= length)
      add_finding(findings, link, "section." + key,
                  key + " = " + shortest_text(value) + (outer ? " m" : " m²") +
                      " gives a section " + (outer ? "" : "about " + shortest_text(width) + " m ") +
                      "as wide as the link is long (" + shortest_text(length) +
                      " m): was it given in millimetres? stiffmsa reads metres");
  }
}

}  // namespace

std::vector<Diagnostic> find_implausible_values(const Model& model) {
  return detail::find_implausible_values(model, detail::ModelIndex(model));
}

std::vector<Diagnostic> detail::find_implausible_values(const Model& model,
                                                        const ModelIndex& index) {
  std::vector<Diagnostic> found;
  const double size = extent(model);
  if (size > kLargestPlausibleModelSize) {
    Origin model_origin;
    model_origin.location.file = model.source_file;
    found.push_back({model_origin.location, "points",
                     "the model is " + shortest_text(std::round(size)) +
                         " m across (the diagonal of its points' box): were the coordinates given "
                         "in millimetres? "
                         "stiffmsa reads metres"});
  }
  std::vector<Finding> findings;
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const Link& link = model.links[l];
    const auto* beam = std::get_if<BeamLink>(&link.kind);
    if (!beam) continue;
    check_modulus(findings, link, "E", beam->material.E);
    if (beam->material.G) check_modulus(findings, link, "G", *beam->material.G);
    if (beam->material.density) check_density(findings, link, *beam->material.density);
    const int from = index.point_of_end(2 * static_cast<int>(l)),
              to = index.point_of_end(2 * static_cast<int>(l) + 1);
    if (from >= 0 && to >= 0)
      check_section_size(findings, link, beam->section,
                         (model.points[static_cast<std::size_t>(to)].position -
                          model.points[static_cast<std::size_t>(from)].position)
                             .norm());
  }
  for (Finding& f : findings) {
    if (f.others > 0)
      f.message +=
          " (and " + std::to_string(f.others) + (f.others == 1 ? " other link)" : " other links)");
    found.push_back({std::move(f.location), std::move(f.key_path), std::move(f.message)});
  }
  return found;
}

void validate(const Model& model) { detail::validate(model, detail::ModelIndex(model)); }

std::vector<Diagnostic> detail::find_value_defects(const Model& model, const ModelIndex& index) {
  return Checker(model, index).run_value_checks();
}

void detail::validate(const Model& model, const ModelIndex& index) {
  auto defects = Checker(model, index).run();
  if (!defects.empty()) throw InputError(std::move(defects));
}

}  // namespace stiffmsa
