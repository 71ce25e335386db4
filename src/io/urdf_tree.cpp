#include "io/urdf_tree.hpp"

#include "stiffmsa/config.hpp"

#if STIFFMSA_HAVE_URDF
#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>
#endif

#include <algorithm>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "model/suggest.hpp"

namespace stiffmsa::detail {

std::optional<int> UrdfTree::find_link(const std::string& name) const {
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i].name == name) return static_cast<int>(i);
  return std::nullopt;
}

std::optional<int> UrdfTree::find_joint(const std::string& name) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == name) return static_cast<int>(i);
  return std::nullopt;
}

std::vector<std::string> UrdfTree::link_names() const {
  std::vector<std::string> names;
  for (const auto& l : links) names.push_back(l.name);
  return names;
}

std::vector<std::string> UrdfTree::joint_names() const {
  std::vector<std::string> names;
  for (const auto& j : joints) names.push_back(j.name);
  return names;
}

bool is_movable(UrdfJointType type) { return type != UrdfJointType::fixed; }

const char* to_string(UrdfJointType type) {
  switch (type) {
    case UrdfJointType::revolute: return "revolute";
    case UrdfJointType::continuous: return "continuous";
    case UrdfJointType::prismatic: return "prismatic";
    case UrdfJointType::fixed: return "fixed";
  }
  return "?";
}

#if STIFFMSA_HAVE_URDF
namespace {

constexpr const char* kUrdfKey = "robot.urdf";

// What TinyXML shows of a <link> or <joint>: its name, its line, and for a joint what the
// checks below need before urdfdom reads it.
struct XmlElement {
  std::string name;
  SourceLocation location;
  std::string type, parent, child;
  bool mimic = false;
};

SourceLocation located(const std::string& file, const TiXmlBase& node) {
  return {file, node.Row(), node.Column()};
}

std::string attribute(const TiXmlElement& element, const char* name) {
  const char* value = element.Attribute(name);
  return value ? value : "";
}

std::string child_link(const TiXmlElement& joint, const char* tag) {
  const TiXmlElement* e = joint.FirstChildElement(tag);
  return e ? attribute(*e, "link") : "";
}

// urdfdom reports through console_bridge's log; its messages are caught here to become the
// InputError's. The handler is process-wide: one parse at a time.
class CollectingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) messages.push_back(text);
  }
  std::vector<std::string> messages;
};

std::mutex urdfdom_mutex;

urdf::ModelInterfaceSharedPtr parse_with_urdfdom(const std::string& text,
                                                 std::vector<std::string>& errors) {
  const std::lock_guard lock(urdfdom_mutex);
  CollectingHandler handler;
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(text);
  } catch (const std::exception& e) {
    handler.messages.push_back(e.what());
  }
  console_bridge::restorePreviousOutputHandler();
  errors = std::move(handler.messages);
  return model;
}

Placement placement_of(const urdf::Pose& pose) {
  double x = 0, y = 0, z = 0, w = 1;
  pose.rotation.getQuaternion(x, y, z, w);
  return {Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix(),
          Vec3(pose.position.x, pose.position.y, pose.position.z)};
}

class UrdfReader {
 public:
  UrdfReader(std::string file, std::string text) : file_(std::move(file)), text_(std::move(text)) {}

  UrdfTree read() {
    TiXmlDocument document;
    document.Parse(text_.c_str());
    if (document.Error())
      throw InputError({file_, document.ErrorRow(), document.ErrorCol()}, kUrdfKey,
                       std::string("the URDF is not well-formed XML (a URDF is an XML file whose "
                                   "root element is <robot>): ") +
                           document.ErrorDesc());
    const TiXmlElement* robot = document.RootElement();
    if (!robot || std::string(robot->Value()) != "robot")
      throw InputError({file_, robot ? robot->Row() : 1, robot ? robot->Column() : 1}, kUrdfKey,
                       "a URDF's root element is <robot>");
    read_elements(*robot);
    check_elements();
    if (!defects_.empty()) throw InputError(std::move(defects_));
    return build(*robot);
  }

 private:
  void fail(const SourceLocation& at, std::string message) {
    defects_.push_back({at, kUrdfKey, std::move(message)});
  }

  void read_elements(const TiXmlElement& robot) {
    for (const TiXmlElement* e = robot.FirstChildElement("link"); e;
         e = e->NextSiblingElement("link"))
      links_.push_back({attribute(*e, "name"), located(file_, *e), {}, {}, {}, false});
    for (const TiXmlElement* e = robot.FirstChildElement("joint"); e;
         e = e->NextSiblingElement("joint"))
      joints_.push_back({attribute(*e, "name"), located(file_, *e), attribute(*e, "type"),
                         child_link(*e, "parent"), child_link(*e, "child"),
                         e->FirstChildElement("mimic") != nullptr});
  }

  const XmlElement* link_named(const std::string& name) const {
    for (const auto& l : links_)
      if (l.name == name) return &l;
    return nullptr;
  }

  std::vector<std::string> link_names() const {
    std::vector<std::string> names;
    for (const auto& l : links_) names.push_back(l.name);
    return names;
  }

  // What stiffmsa cannot model, said with the joint's or link's name and line; urdfdom
  // would refuse some of it too, but with neither.
  void check_elements() {
    if (links_.empty()) fail({file_, 1, 1}, "the URDF has no <link>");
    std::map<std::string, const XmlElement*> seen;
    for (const auto& l : links_) {
      if (l.name.empty())
        fail(l.location, "a <link> without a name");
      else if (!seen.emplace(l.name, &l).second)
        fail(l.location, "a second link named '" + l.name + "'");
    }
    std::map<std::string, const XmlElement*> parent_joint;
    std::map<std::string, const XmlElement*> joint_seen;
    const std::vector<std::string> known{"revolute", "continuous", "prismatic", "fixed"};
    for (const auto& j : joints_) {
      const std::string what = "joint '" + j.name + "'";
      if (j.name.empty()) {
        fail(j.location, "a <joint> without a name");
        continue;
      }
      if (!joint_seen.emplace(j.name, &j).second)
        fail(j.location, "a second joint named '" + j.name + "'");
      if (j.type == "floating" || j.type == "planar")
        fail(j.location,
             what + " is " + j.type +
                 ": stiffmsa reads revolute, continuous, prismatic and fixed joints (a " + j.type +
                 " joint has no stiffness to give; model what holds it in the model file instead)");
      else if (std::find(known.begin(), known.end(), j.type) == known.end())
        fail(j.location, what + " has the unknown type '" + j.type + "'" +
                             suggestion(j.type, known, "types are"));
      if (j.mimic)
        fail(j.location,
             what +
                 " mimics another joint: stiffmsa does not read <mimic> (a coupled joint's "
                 "stiffness is that of its drive; write the coupling as joints in the model file)");
      for (const auto& [role, link] :
           {std::pair{"parent", j.parent}, std::pair{"child", j.child}}) {
        if (link.empty())
          fail(j.location, what + " has no <" + std::string(role) + " link=\"...\"/>");
        else if (!link_named(link))
          fail(j.location, what + ": its " + role + " link '" + link + "' is not in the URDF" +
                               suggestion(link, link_names(), "links are"));
      }
      if (j.child.empty()) continue;
      if (const auto [other, is_new] = parent_joint.emplace(j.child, &j); !is_new)
        fail(j.location, "the URDF is not a tree: link '" + j.child + "' is the child of joint '" +
                             other->second->name + "' (line " +
                             std::to_string(other->second->location.line) + ") and of " + what);
    }
    if (!defects_.empty()) return;
    std::vector<std::string> roots;
    for (const auto& l : links_)
      if (!parent_joint.count(l.name)) roots.push_back(l.name);
    if (roots.size() != 1) {
      fail(roots.empty() ? links_.front().location : link_named(roots[1])->location,
           roots.empty()
               ? "the URDF is not a tree: its joints close a loop (every link has a parent)"
               : "the URDF is not a tree: it has several root links (" + comma_list(roots) +
                     "); join them with joints, or describe each robot in a URDF of its own");
      return;
    }
    // One root and one parent per link: a loop is a part the root cannot reach.
    std::vector<std::string> reached{roots.front()};
    for (std::size_t k = 0; k < reached.size(); ++k)
      for (const auto& j : joints_)
        if (j.parent == reached[k]) reached.push_back(j.child);
    if (reached.size() != links_.size())
      for (const auto& j : joints_)
        if (std::find(reached.begin(), reached.end(), j.child) == reached.end()) {
          fail(j.location, "the URDF is not a tree: joint '" + j.name +
                               "' is in a loop that the root link '" + roots.front() +
                               "' does not reach");
          return;
        }
  }

  // Where urdfdom's message names a joint or link in brackets ("Joint [j2] ..."), its line.
  SourceLocation location_in(const std::string& message) const {
    for (std::size_t open = message.find('['); open != std::string::npos;
         open = message.find('[', open + 1)) {
      const std::size_t close = message.find(']', open);
      if (close == std::string::npos) break;
      const std::string name = message.substr(open + 1, close - open - 1);
      for (const auto& j : joints_)
        if (j.name == name) return j.location;
      if (const XmlElement* l = link_named(name)) return l->location;
    }
    return {file_, 0, 0};
  }

  UrdfTree build(const TiXmlElement& robot) {
    std::vector<std::string> errors;
    const urdf::ModelInterfaceSharedPtr model = parse_with_urdfdom(text_, errors);
    if (!model) {
      if (errors.empty()) errors.push_back("urdfdom could not read it");
      std::vector<Diagnostic> defects;
      for (const auto& e : errors) defects.push_back({location_in(e), kUrdfKey, "urdfdom: " + e});
      throw InputError(std::move(defects));
    }
    UrdfTree tree;
    tree.file = file_;
    tree.name = attribute(robot, "name");
    // Depth first from the root, children in the file's order.
    std::vector<std::pair<const XmlElement*, int>> stack{{link_named(model->getRoot()->name), -1}};
    while (!stack.empty()) {
      const auto [element, parent_joint] = stack.back();
      stack.pop_back();
      const int index = static_cast<int>(tree.links.size());
      UrdfLink link;
      link.name = element->name;
      link.location = element->location;
      link.parent_joint = parent_joint;
      if (const auto inertial = model->getLink(link.name)->inertial) {
        link.mass = inertial->mass;
        link.centre_of_mass = placement_of(inertial->origin).translation;
      }
      if (parent_joint >= 0) {
        tree.joints[static_cast<std::size_t>(parent_joint)].child = index;
        tree.links[static_cast<std::size_t>(
                       tree.joints[static_cast<std::size_t>(parent_joint)].parent)]
            .child_joints.push_back(parent_joint);
      }
      tree.links.push_back(std::move(link));
      std::vector<std::pair<const XmlElement*, int>> children;
      for (const auto& j : joints_) {
        if (j.parent != element->name) continue;
        children.emplace_back(link_named(j.child), static_cast<int>(tree.joints.size()));
        tree.joints.push_back(joint_of(j, *model->getJoint(j.name), index));
      }
      stack.insert(stack.end(), children.rbegin(), children.rend());
    }
    return tree;
  }

  static UrdfJoint joint_of(const XmlElement& element, const urdf::Joint& joint, int parent) {
    UrdfJoint j;
    j.name = element.name;
    j.type = element.type == "revolute"     ? UrdfJointType::revolute
             : element.type == "continuous" ? UrdfJointType::continuous
             : element.type == "prismatic"  ? UrdfJointType::prismatic
                                            : UrdfJointType::fixed;
    j.parent = parent;
    j.origin = placement_of(joint.parent_to_joint_origin_transform);
    j.axis = Vec3(joint.axis.x, joint.axis.y, joint.axis.z);
    if (j.axis.norm() > 0) j.axis.normalize();
    if ((j.type == UrdfJointType::revolute || j.type == UrdfJointType::prismatic) && joint.limits) {
      j.lower = joint.limits->lower;
      j.upper = joint.limits->upper;
    }
    j.location = element.location;
    return j;
  }

  std::string file_;
  std::string text_;
  std::vector<XmlElement> links_;
  std::vector<XmlElement> joints_;
  std::vector<Diagnostic> defects_;
};

}  // namespace

UrdfTree read_urdf(const std::filesystem::path& path, const SourceLocation& referenced_at,
                   const std::string& key) {
  std::error_code error;
  if (!std::filesystem::exists(path, error))
    throw InputError(referenced_at, key, "the URDF file '" + path.string() + "' does not exist");
  if (std::filesystem::is_directory(path, error))
    throw InputError(referenced_at, key, "the URDF file '" + path.string() + "' is a directory");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in)
    throw InputError(referenced_at, key, "cannot read the URDF file '" + path.string() + "'");
  return UrdfReader(path.string(), text.str()).read();
}
#else
UrdfTree read_urdf(const std::filesystem::path&, const SourceLocation& referenced_at,
                   const std::string& key) {
  throw InputError(referenced_at, key,
                   "this build of stiffmsa reads no URDF files (built without urdfdom and TinyXML: "
                   "install liburdfdom-dev and libtinyxml-dev and build again)");
}
#endif

}  // namespace stiffmsa::detail
