#pragma once
// The model: plain data describing a manipulator exactly as the user named it. It holds no
// index maps, matrices or results; those live in a Workspace (analysis.hpp). A model is
// checked with validate() (validate.hpp) before it is solved.
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/types.hpp"

namespace stiffmsa {

// Where an entity and each of its keys came from in a model file (empty for API models).
struct Origin {
  SourceLocation location;                           // the entity's own mapping
  std::map<std::string, SourceLocation> key_locations;  // per key, e.g. "axis"

  // The location of `key` if recorded, else the entity's own location.
  const SourceLocation& of(const std::string& key) const;
};

struct Point {
  std::string name;
  Vec3 position = Vec3::Zero();
  Origin origin;
};

// ---- links -------------------------------------------------------------------------------

struct Material {
  double E = 0;
  std::optional<double> nu;  // exactly one of nu or G
  std::optional<double> G;
};

enum class SectionShape { circle, tube, rect, rect_tube, generic };

// Dimensions by shape (sections.md): circle{D}, tube{D,t}, rect{b,h}, rect_tube{b,h,t},
// generic{A,Iy,Iz,J}. Asy/Asz override the shape's shear areas.
struct Section {
  SectionShape shape = SectionShape::generic;
  double D = 0, t = 0, b = 0, h = 0;
  double A = 0, Iy = 0, Iz = 0, J = 0;
  std::optional<double> Asy, Asz;

  static Section circle(double D);
  static Section tube(double D, double t);
  static Section rect(double b, double h);
  static Section rect_tube(double b, double h, double t);
  static Section generic(double A, double Iy, double Iz, double J);
};

// Properties of a section as the beam element uses them.
struct SectionProperties {
  double A = 0, Iy = 0, Iz = 0, J = 0;
  std::optional<double> Asy, Asz;  // absent where neither the shape nor the user gives one
};

enum class LinkFrame { global, local };

struct BeamLink {
  Material material;
  Section section;
  bool shear = false;  // Timoshenko
  std::optional<Vec3> zref;
};
struct RigidLink {};
// CAD-based link: 12×12 free-free stiffness over [Δt_from; Δt_to].
struct MatrixLink {
  Mat12 K = Mat12::Zero();
  LinkFrame frame = LinkFrame::global;
  std::optional<Vec3> zref;
};
// CAD-based link: 6×6 compliance of end `to` with end `from` clamped.
struct ComplianceLink {
  Mat6 C = Mat6::Zero();
  LinkFrame frame = LinkFrame::global;
  std::optional<Vec3> zref;
};

using LinkKind = std::variant<BeamLink, RigidLink, MatrixLink, ComplianceLink>;

struct Link {
  std::string name;
  std::string from, to;  // point names
  LinkKind kind;
  Origin origin;
};

// ---- joints and supports -----------------------------------------------------------------

enum class JointType { rigid, revolute, prismatic, cylindrical, universal, spherical, planar, custom };

// The free directions of a joint or support (model-format.md, "free directions").
struct Kinematics {
  JointType type = JointType::rigid;
  Vec3 axis = Vec3::Zero();            // revolute, prismatic, cylindrical
  Vec3 axis_b = Vec3::Zero();          // universal: axes [axis, axis_b]
  Vec3 normal = Vec3::Zero();          // planar
  std::vector<Vec6> free_rows;         // custom, as given

  static Kinematics rigid();
  static Kinematics revolute(const Vec3& axis);
  static Kinematics prismatic(const Vec3& axis);
  static Kinematics cylindrical(const Vec3& axis);
  static Kinematics universal(const Vec3& a, const Vec3& b);
  static Kinematics spherical();
  static Kinematics planar(const Vec3& normal);
  static Kinematics custom(std::vector<Vec6> rows);
};

// Number of free directions p of a joint type (custom: its row count).
int free_direction_count(const Kinematics& k);

// What a joint or support does along its free directions.
struct Connection {
  Kinematics kinematics;
  std::optional<MatX> stiffness;  // p×p, symmetric positive definite: elastic
  std::optional<VecX> preload;    // p: generalised force at zero relative deflection
  bool actuated = false;          // without stiffness: locked (rigid), effort reported
};

struct Joint {
  std::string name;
  std::string at;                  // point
  std::vector<std::string> links;  // m >= 2 link ends at `at`, first is "end 1"
  Connection connection;
  Origin origin;
};

struct Support {
  std::string name;
  std::string at;
  std::vector<std::string> links;  // empty: every link end at the point
  Connection connection;
  Origin origin;
};

// ---- loads and end effectors -------------------------------------------------------------

struct Load {
  std::string at;
  std::optional<std::string> link;  // may be left out where one link end is at the point
  Vec6 wrench = Vec6::Zero();       // [F; M] global, moment about `at`
  // A robot link's weight (docs/urdf.md): the result also gives the end effectors' deflection
  // under these loads alone.
  bool self_weight = false;
  Origin origin;
};

struct EndEffector {
  std::string name;
  std::string at;
  std::optional<std::string> link;
  // Results in these axes too (columns: the axes in world axes), e.g. a robot frame's.
  std::optional<Mat3> axes;
  Origin origin;
};

// ---- the model ---------------------------------------------------------------------------

enum class LinkEnd { from = 0, to = 1 };

// Settings a model file may carry for its own analysis (top-level `options:`).
struct ModelOptions {
  // Solve despite free motions that move no end effector (the spin of an S-P-S leg about its
  // own axis): the end-effector results do not depend on them.
  bool accept_idle_motions = false;
};

// A parameter of a parametric model (parametric.hpp) at the value a model was built for.
struct ParameterValue {
  std::string name;
  double value = 0;
  std::string unit;  // as the file gives it; may be empty
  bool set = false;  // given by the user (`--set`), not the file's default
};

struct Model {
  std::string name = "model";
  // A model file's `parameters:` at the values this model was built for (the defaults, or
  // the settings of load_model_family); empty for a file without parameters and API models.
  // For the record only: the numbers they gave are already in the model.
  std::vector<ParameterValue> parameters;
  ModelOptions options;
  std::string source_file;  // empty for API models
  std::vector<Point> points;
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<Support> supports;
  std::vector<Load> loads;
  std::vector<EndEffector> end_effectors;
  // What the reader noticed that does not make the model invalid (a robot's joint position
  // outside its limits); a solve reports them among its warnings.
  std::vector<Diagnostic> warnings;

  // Verbs for building a model in code; each returns the new entity for further settings.
  Point& add_point(std::string name, const Vec3& position);
  Link& add_beam(std::string name, std::string from, std::string to, const Material& material,
                 const Section& section);
  Link& add_rigid_link(std::string name, std::string from, std::string to);
  Link& add_matrix_link(std::string name, std::string from, std::string to, const Mat12& K,
                        LinkFrame frame = LinkFrame::global);
  Link& add_compliance_link(std::string name, std::string from, std::string to, const Mat6& C,
                            LinkFrame frame = LinkFrame::global);
  Joint& add_joint(std::string name, std::string at, std::vector<std::string> links,
                   Connection connection);
  Support& add_support(std::string name, std::string at, std::vector<std::string> links,
                       Connection connection);
  Load& add_load(std::string at, std::optional<std::string> link, const Vec6& wrench);
  EndEffector& add_end_effector(std::string name, std::string at,
                                std::optional<std::string> link = std::nullopt);

  // Lookups by name (nullptr when absent).
  const Point* find_point(const std::string& name) const;
  const Link* find_link(const std::string& name) const;
};

// Shear modulus of a material: G, or E/(2(1+nu)).
double shear_modulus(const Material& m);

// A, Iy, Iz, J and shear areas of a section (sections.md).
SectionProperties section_properties(const Section& s);

// Enum <-> string pairs for every name a user can write.
const char* to_string(JointType t);
std::optional<JointType> joint_type_from_string(const std::string& s);
const char* to_string(SectionShape s);
std::optional<SectionShape> section_shape_from_string(const std::string& s);
const char* to_string(LinkEnd e);

}  // namespace stiffmsa
