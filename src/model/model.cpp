#include "stiffmsa/model.hpp"

#include <array>
#include <sstream>
#include <utility>

namespace stiffmsa {

std::string Diagnostic::to_string() const {
  std::ostringstream out;
  if (!location.file.empty()) {
    out << location.file;
    if (location.line > 0) {
      out << ':' << location.line;
      if (location.column > 0) out << ':' << location.column;
    }
    out << ": ";
  }
  if (!key_path.empty()) out << key_path << ": ";
  out << message;
  return out.str();
}

namespace {
std::string join_diagnostics(const std::vector<Diagnostic>& diagnostics) {
  std::string text = diagnostics.size() == 1 ? "invalid model: " : "invalid model (" +
                     std::to_string(diagnostics.size()) + " defects): ";
  for (std::size_t i = 0; i < diagnostics.size(); ++i) {
    if (i > 0) text += "; ";
    text += diagnostics[i].to_string();
  }
  return text;
}
}  // namespace

InputError::InputError(std::vector<Diagnostic> diagnostics)
    : Error(join_diagnostics(diagnostics)), diagnostics_(std::move(diagnostics)) {}

InputError::InputError(SourceLocation location, std::string key_path, std::string message)
    : InputError(std::vector<Diagnostic>{
          Diagnostic{std::move(location), std::move(key_path), std::move(message)}}) {}

namespace {
std::string summary_and_details(const std::string& summary, const std::vector<std::string>& details) {
  std::string text = summary;
  for (const std::string& detail : details) text += "\n  " + detail;
  return text;
}
}  // namespace

SingularModelError::SingularModelError(Cause cause, std::string summary, std::vector<std::string> details)
    : Error(summary_and_details(summary, details)),
      cause_(cause),
      summary_(std::move(summary)),
      details_(std::move(details)) {}

const SourceLocation& Origin::of(const std::string& key) const {
  auto it = key_locations.find(key);
  return it != key_locations.end() ? it->second : location;
}

Kinematics Kinematics::rigid() { return {}; }
Kinematics Kinematics::revolute(const Vec3& axis) {
  Kinematics k;
  k.type = JointType::revolute;
  k.axis = axis;
  return k;
}
Kinematics Kinematics::prismatic(const Vec3& axis) {
  Kinematics k = revolute(axis);
  k.type = JointType::prismatic;
  return k;
}
Kinematics Kinematics::cylindrical(const Vec3& axis) {
  Kinematics k = revolute(axis);
  k.type = JointType::cylindrical;
  return k;
}
Kinematics Kinematics::universal(const Vec3& a, const Vec3& b) {
  Kinematics k;
  k.type = JointType::universal;
  k.axis = a;
  k.axis_b = b;
  return k;
}
Kinematics Kinematics::spherical() {
  Kinematics k;
  k.type = JointType::spherical;
  return k;
}
Kinematics Kinematics::planar(const Vec3& normal) {
  Kinematics k;
  k.type = JointType::planar;
  k.normal = normal;
  return k;
}
Kinematics Kinematics::custom(std::vector<Vec6> rows) {
  Kinematics k;
  k.type = JointType::custom;
  k.free_rows = std::move(rows);
  return k;
}

int free_direction_count(const Kinematics& k) {
  switch (k.type) {
    case JointType::rigid: return 0;
    case JointType::revolute:
    case JointType::prismatic: return 1;
    case JointType::cylindrical:
    case JointType::universal: return 2;
    case JointType::spherical:
    case JointType::planar: return 3;
    case JointType::custom: return static_cast<int>(k.free_rows.size());
  }
  return 0;
}

Point& Model::add_point(std::string name, const Vec3& position) {
  points.push_back(Point{std::move(name), position, {}});
  return points.back();
}

namespace {
Link& push_link(Model& m, std::string name, std::string from, std::string to, LinkKind kind) {
  m.links.push_back(Link{std::move(name), std::move(from), std::move(to), std::move(kind), {}});
  return m.links.back();
}
}  // namespace

Link& Model::add_beam(std::string name, std::string from, std::string to, const Material& material,
                      const Section& section) {
  return push_link(*this, std::move(name), std::move(from), std::move(to),
                   BeamLink{material, section, false, std::nullopt});
}
Link& Model::add_rigid_link(std::string name, std::string from, std::string to) {
  return push_link(*this, std::move(name), std::move(from), std::move(to), RigidLink{});
}
Link& Model::add_matrix_link(std::string name, std::string from, std::string to, const Mat12& K,
                             LinkFrame frame) {
  return push_link(*this, std::move(name), std::move(from), std::move(to),
                   MatrixLink{K, frame, std::nullopt});
}
Link& Model::add_compliance_link(std::string name, std::string from, std::string to,
                                 const Mat6& C, LinkFrame frame) {
  return push_link(*this, std::move(name), std::move(from), std::move(to),
                   ComplianceLink{C, frame, std::nullopt});
}
Joint& Model::add_joint(std::string name, std::string at, std::vector<std::string> link_names,
                        Connection connection) {
  joints.push_back(Joint{std::move(name), std::move(at), std::move(link_names),
                         std::move(connection), {}});
  return joints.back();
}
Support& Model::add_support(std::string name, std::string at, std::vector<std::string> link_names,
                            Connection connection) {
  supports.push_back(Support{std::move(name), std::move(at), std::move(link_names),
                             std::move(connection), {}});
  return supports.back();
}
Load& Model::add_load(std::string at, std::optional<std::string> link, const Vec6& wrench) {
  loads.push_back(Load{std::move(at), std::move(link), wrench, false, {}});
  return loads.back();
}
EndEffector& Model::add_end_effector(std::string name, std::string at,
                                     std::optional<std::string> link) {
  end_effectors.push_back(EndEffector{std::move(name), std::move(at), std::move(link), std::nullopt, {}});
  return end_effectors.back();
}

const Point* Model::find_point(const std::string& name) const {
  for (const auto& p : points)
    if (p.name == name) return &p;
  return nullptr;
}
const Link* Model::find_link(const std::string& name) const {
  for (const auto& l : links)
    if (l.name == name) return &l;
  return nullptr;
}

namespace {
constexpr std::array<std::pair<JointType, const char*>, 8> kJointTypeNames{{
    {JointType::rigid, "rigid"},
    {JointType::revolute, "revolute"},
    {JointType::prismatic, "prismatic"},
    {JointType::cylindrical, "cylindrical"},
    {JointType::universal, "universal"},
    {JointType::spherical, "spherical"},
    {JointType::planar, "planar"},
    {JointType::custom, "custom"},
}};
constexpr std::array<std::pair<SectionShape, const char*>, 5> kShapeNames{{
    {SectionShape::circle, "circle"},
    {SectionShape::tube, "tube"},
    {SectionShape::rect, "rect"},
    {SectionShape::rect_tube, "rect_tube"},
    {SectionShape::generic, "generic"},
}};

template <class Enum, std::size_t N>
const char* name_of(const std::array<std::pair<Enum, const char*>, N>& table, Enum value) {
  for (const auto& [e, name] : table)
    if (e == value) return name;
  return "?";
}
template <class Enum, std::size_t N>
std::optional<Enum> value_of(const std::array<std::pair<Enum, const char*>, N>& table,
                             const std::string& text) {
  for (const auto& [e, name] : table)
    if (text == name) return e;
  return std::nullopt;
}
}  // namespace

const char* to_string(JointType t) { return name_of(kJointTypeNames, t); }
std::optional<JointType> joint_type_from_string(const std::string& s) {
  return value_of(kJointTypeNames, s);
}
const char* to_string(SectionShape s) { return name_of(kShapeNames, s); }
std::optional<SectionShape> section_shape_from_string(const std::string& s) {
  return value_of(kShapeNames, s);
}
const char* to_string(LinkEnd e) { return e == LinkEnd::from ? "from" : "to"; }

}  // namespace stiffmsa
