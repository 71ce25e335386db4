// A Model written back as a plain model file (format stiffmsa/1, model-format.md): what
// `stiffmsa expand` shows of the model a robot block generates. Flow style, one entity per line,
// every number with 17 significant digits, so that the file reads back to the same doubles.
#include <cstdio>
#include <sstream>
#include <string>
#include <variant>

#include "model/value_checks.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa {
namespace {

std::string number(double x) { return shortest_text(x); }

// Names in double quotes (JSON's escapes), whatever they hold.
std::string quoted(const std::string& name) {
  std::string text = "\"";
  for (const char c : name) {
    if (c == '"' || c == '\\') text += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", c);
      text += escape;
      continue;
    }
    text += c;
  }
  return text + "\"";
}

template <class Dense>
std::string list(const Dense& v) {
  std::string text = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) text += (i ? ", " : "") + number(v.data()[i]);
  return text + "]";
}

std::string matrix(const MatX& m) {
  std::string text = "[";
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    text += (r ? ", " : "") + list(VecX(m.row(r).transpose()));
  return text + "]";
}

std::string names(const std::vector<std::string>& items) {
  std::string text = "[";
  for (std::size_t i = 0; i < items.size(); ++i) text += (i ? ", " : "") + quoted(items[i]);
  return text + "]";
}

std::string material(const Material& m) {
  std::string text = "{E: " + number(m.E);
  if (m.nu) text += ", nu: " + number(*m.nu);
  if (m.G) text += ", G: " + number(*m.G);
  if (m.density) text += ", density: " + number(*m.density);
  return text + "}";
}

std::string section(const Section& s) {
  std::string text = std::string("{shape: ") + to_string(s.shape);
  for (const auto& d : detail::section_dimensions(s.shape))
    text += ", " + std::string(d.key) + ": " + number(s.*d.value);
  if (s.Asy) text += ", Asy: " + number(*s.Asy);
  if (s.Asz) text += ", Asz: " + number(*s.Asz);
  return text + "}";
}

std::string frame(LinkFrame f, const std::optional<Vec3>& zref) {
  std::string text = std::string(", frame: ") + (f == LinkFrame::local ? "local" : "global");
  if (zref) text += ", zref: " + list(*zref);
  return text;
}

std::string link(const Link& l) {
  const std::string ends = ", from: " + quoted(l.from) + ", to: " + quoted(l.to);
  if (const auto* beam = std::get_if<BeamLink>(&l.kind)) {
    std::string text = "{type: beam" + ends + ", material: " + material(beam->material) +
                       ", section: " + section(beam->section);
    if (beam->shear) text += ", shear: true";
    if (beam->zref) text += ", zref: " + list(*beam->zref);
    return text + "}";
  }
  if (const auto* m = std::get_if<MatrixLink>(&l.kind))
    return "{type: matrix" + ends + ", K: " + matrix(m->K) + frame(m->frame, m->zref) + "}";
  if (const auto* c = std::get_if<ComplianceLink>(&l.kind))
    return "{type: compliance" + ends + ", C: " + matrix(c->C) + frame(c->frame, c->zref) + "}";
  return "{type: rigid" + ends + "}";
}

std::string connection(const Connection& c) {
  const Kinematics& k = c.kinematics;
  std::string text = std::string("type: ") + to_string(k.type);
  switch (k.type) {
    case JointType::revolute:
    case JointType::prismatic:
    case JointType::cylindrical: text += ", axis: " + list(k.axis); break;
    case JointType::universal:
      text += ", axes: [" + list(k.axis) + ", " + list(k.axis_b) + "]";
      break;
    case JointType::planar: text += ", normal: " + list(k.normal); break;
    case JointType::custom: {
      text += ", free: [";
      for (std::size_t i = 0; i < k.free_rows.size(); ++i)
        text += (i ? ", " : "") + list(k.free_rows[i]);
      text += "]";
      break;
    }
    case JointType::rigid:
    case JointType::spherical: break;
  }
  if (c.stiffness) text += ", stiffness: " + matrix(*c.stiffness);
  if (c.preload) text += ", preload: " + list(*c.preload);
  if (c.is_actuated) text += ", actuated: true";
  return text;
}

// One list of loads: those on points, then those along links (a file keeps them in one list).
void write_loads(std::ostringstream& out, const std::string& indent, const std::vector<Load>& loads,
                 const std::vector<LinkLoad>& link_loads) {
  for (const Load& l : loads) {
    out << indent << "- {at: " << quoted(l.at);
    if (l.link) out << ", link: " << quoted(*l.link);
    out << ", wrench: " << list(l.wrench);
    if (l.self_weight) out << ", self_weight: true";
    out << "}\n";
  }
  for (const LinkLoad& l : link_loads) {
    out << indent << "- {link: " << quoted(l.link);
    if (const auto* d = std::get_if<DistributedLinkLoad>(&l.load))
      out << ", distributed: {from: " << list(d->from) << ", to: " << list(d->to) << "}";
    else if (const auto* p = std::get_if<PointLinkLoad>(&l.load))
      out << ", force: " << list(p->force) << ", moment: " << list(p->moment)
          << ", position: " << number(p->position);
    out << "}\n";
  }
}

}  // namespace

std::string model_to_yaml(const Model& model) {
  std::ostringstream out;
  out << "format: stiffmsa/1\nname: " << quoted(model.name) << "\n";
  if (model.options.accept_idle_motions) out << "options: {accept_idle_motions: true}\n";
  if (model.options.mode != AnalysisMode::linear || model.options.load_steps) {
    out << "analysis: {mode: " << to_string(model.options.mode);
    if (model.options.load_steps) out << ", load_steps: " << *model.options.load_steps;
    out << "}\n";
  }
  out << "points:\n";
  for (const Point& p : model.points)
    out << "  " << quoted(p.name) << ": " << list(p.position) << "\n";
  out << "links:\n";
  for (const Link& l : model.links) out << "  " << quoted(l.name) << ": " << link(l) << "\n";
  if (!model.joints.empty()) out << "joints:\n";
  for (const Joint& j : model.joints)
    out << "  " << quoted(j.name) << ": {" << connection(j.connection) << ", at: " << quoted(j.at)
        << ", links: " << names(j.links) << "}\n";
  if (!model.supports.empty()) out << "supports:\n";
  for (const Support& s : model.supports) {
    out << "  " << quoted(s.name) << ": {" << connection(s.connection) << ", at: " << quoted(s.at);
    if (!s.links.empty()) out << ", links: " << names(s.links);
    if (s.displacement) out << ", displacement: " << list(*s.displacement);
    out << "}\n";
  }
  if (!model.loads.empty() || !model.link_loads.empty()) out << "loads:\n";
  write_loads(out, "  ", model.loads, model.link_loads);
  if (model.gravity) out << "gravity: " << list(*model.gravity) << "\n";
  if (!model.load_cases.empty()) out << "load_cases:\n";
  for (const LoadCase& c : model.load_cases) {
    out << "  " << quoted(c.name) << ":\n";
    if (c.gravity) out << "    gravity: " << list(*c.gravity) << "\n";
    out << "    loads:" << (c.loads.empty() && c.link_loads.empty() ? " []" : "") << "\n";
    write_loads(out, "      ", c.loads, c.link_loads);
  }
  if (!model.end_effectors.empty()) out << "end_effectors:\n";
  for (const EndEffector& e : model.end_effectors) {
    out << "  " << quoted(e.name) << ": {at: " << quoted(e.at);
    if (e.link) out << ", link: " << quoted(*e.link);
    out << "}\n";
  }
  return out.str();
}

void write_model_file(const Model& model, const std::filesystem::path& path) {
  write_file_atomically(path, model_to_yaml(model));
}

}  // namespace stiffmsa
