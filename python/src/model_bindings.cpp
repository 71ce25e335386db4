// Model building from Python: the builder's verbs (Model::add_*), the values they take
// (Material, Section, Kinematics, Connection), load_model and check.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <sstream>

#include "convert.hpp"

namespace stiffmsa::python {

namespace {

// ---- a model as plain Python data (to_dict), for comparing and inspecting ---------------

py::list rows_of(const MatX& matrix) {
  py::list rows;
  for (Eigen::Index r = 0; r < matrix.rows(); ++r) {
    py::list row;
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) row.append(matrix(r, c));
    rows.append(row);
  }
  return rows;
}

py::list list_of(const VecX& vector) {
  py::list values;
  for (Eigen::Index i = 0; i < vector.size(); ++i) values.append(vector[i]);
  return values;
}

template <class T>
py::object optional_of(const std::optional<T>& value) {
  if (!value) return py::none();
  return py::cast(*value);
}

py::object optional_list(const std::optional<Vec3>& value) {
  return value ? py::object(list_of(*value)) : py::none();
}

py::dict section_dict(const Section& s) {
  py::dict d;
  d["shape"] = to_string(s.shape);
  switch (s.shape) {
    case SectionShape::circle: d["D"] = s.D; break;
    case SectionShape::tube:
      d["D"] = s.D;
      d["t"] = s.t;
      break;
    case SectionShape::rect:
      d["b"] = s.b;
      d["h"] = s.h;
      break;
    case SectionShape::rect_tube:
      d["b"] = s.b;
      d["h"] = s.h;
      d["t"] = s.t;
      break;
    case SectionShape::generic:
      d["A"] = s.A;
      d["Iy"] = s.Iy;
      d["Iz"] = s.Iz;
      d["J"] = s.J;
      break;
  }
  d["Asy"] = optional_of(s.Asy);
  d["Asz"] = optional_of(s.Asz);
  return d;
}

py::dict link_dict(const Link& link) {
  py::dict d;
  d["from"] = link.from;
  d["to"] = link.to;
  std::visit(
      [&](const auto& kind) {
        using Kind = std::decay_t<decltype(kind)>;
        if constexpr (std::is_same_v<Kind, BeamLink>) {
          d["type"] = "beam";
          d["material"] = py::dict(py::arg("E") = kind.material.E,
                                   py::arg("nu") = optional_of(kind.material.nu),
                                   py::arg("G") = optional_of(kind.material.G));
          // Issue 22's keys appear where given, so that older models' dicts are as they were.
          if (kind.material.density) d["material"]["density"] = *kind.material.density;
          d["section"] = section_dict(kind.section);
          d["shear"] = kind.shear;
          d["zref"] = optional_list(kind.zref);
        } else if constexpr (std::is_same_v<Kind, RigidLink>) {
          d["type"] = "rigid";
        } else {
          d["type"] = std::is_same_v<Kind, MatrixLink> ? "matrix" : "compliance";
          if constexpr (std::is_same_v<Kind, MatrixLink>)
            d["K"] = rows_of(kind.K);
          else
            d["C"] = rows_of(kind.C);
          d["frame"] = kind.frame == LinkFrame::global ? "global" : "local";
          d["zref"] = optional_list(kind.zref);
        }
      },
      link.kind);
  return d;
}

py::dict connection_dict(const std::string& at, const std::vector<std::string>& links,
                         const Connection& c) {
  const Kinematics& k = c.kinematics;
  py::dict d;
  d["at"] = at;
  d["links"] = links;
  d["type"] = to_string(k.type);
  switch (k.type) {
    case JointType::revolute:
    case JointType::prismatic:
    case JointType::cylindrical: d["axis"] = list_of(k.axis); break;
    case JointType::universal:
      d["axes"] = py::make_tuple(list_of(k.axis), list_of(k.axis_b));
      break;
    case JointType::planar: d["normal"] = list_of(k.normal); break;
    case JointType::custom: {
      py::list rows;
      for (const auto& row : k.free_rows) rows.append(list_of(row));
      d["free"] = rows;
      break;
    }
    default: break;
  }
  d["stiffness"] = c.stiffness ? py::object(rows_of(*c.stiffness)) : py::none();
  d["preload"] = c.preload ? py::object(list_of(*c.preload)) : py::none();
  d["actuated"] = c.is_actuated;
  return d;
}

py::dict load_dict(const Load& l) {
  py::dict d(py::arg("at") = l.at, py::arg("link") = optional_of(l.link),
             py::arg("wrench") = list_of(l.wrench));
  if (l.self_weight) d["self_weight"] = true;
  return d;
}

// As a model file writes a load along a link.
py::dict link_load_dict(const LinkLoad& l) {
  py::dict d;
  d["link"] = l.link;
  if (const auto* q = std::get_if<DistributedLinkLoad>(&l.load)) {
    d["distributed"] = py::dict(py::arg("from") = list_of(q->from), py::arg("to") = list_of(q->to));
  } else if (const auto* p = std::get_if<PointLinkLoad>(&l.load)) {
    d["force"] = list_of(p->force);
    d["moment"] = list_of(p->moment);
    d["position"] = p->position;
  }
  return d;
}

// Point loads, then loads along links: one list, as in a model file.
py::list loads_list(const std::vector<Load>& loads, const std::vector<LinkLoad>& link_loads) {
  py::list list;
  for (const auto& l : loads) list.append(load_dict(l));
  for (const auto& l : link_loads) list.append(link_load_dict(l));
  return list;
}

py::dict model_dict(const Model& model) {
  py::dict d, points, links, joints, supports, end_effectors;
  py::list loads;
  d["name"] = model.name;
  d["options"] = py::dict(py::arg("accept_idle_motions") = model.options.accept_idle_motions);
  for (const auto& p : model.points) points[py::str(p.name)] = list_of(p.position);
  for (const auto& l : model.links) links[py::str(l.name)] = link_dict(l);
  for (const auto& j : model.joints)
    joints[py::str(j.name)] = connection_dict(j.at, j.links, j.connection);
  for (const auto& s : model.supports) {
    py::dict support = connection_dict(s.at, s.links, s.connection);
    if (s.displacement) support["displacement"] = list_of(*s.displacement);
    supports[py::str(s.name)] = support;
  }
  loads = loads_list(model.loads, model.link_loads);
  if (model.options.mode != AnalysisMode::linear || model.options.load_steps)
    d["analysis"] = py::dict(py::arg("mode") = to_string(model.options.mode),
                             py::arg("load_steps") = optional_of(model.options.load_steps));
  if (model.gravity) d["gravity"] = list_of(*model.gravity);
  if (!model.load_cases.empty()) {
    py::dict cases;
    for (const auto& c : model.load_cases)
      cases[py::str(c.name)] =
          py::dict(py::arg("loads") = loads_list(c.loads, c.link_loads),
                   py::arg("gravity") = c.gravity ? py::object(list_of(*c.gravity)) : py::none());
    d["load_cases"] = cases;
  }
  for (const auto& e : model.end_effectors)
    end_effectors[py::str(e.name)] =
        py::dict(py::arg("at") = e.at, py::arg("link") = optional_of(e.link));
  d["points"] = points;
  d["links"] = links;
  d["joints"] = joints;
  d["supports"] = supports;
  d["loads"] = loads;
  d["end_effectors"] = end_effectors;
  return d;
}

std::string count_text(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string model_repr(const Model& m) {
  return "<stiffmsa.Model '" + m.name + "': " + count_text(m.points.size(), "point", "points") +
         ", " + count_text(m.links.size(), "link", "links") + ", " +
         count_text(m.joints.size(), "joint", "joints") + ", " +
         count_text(m.supports.size(), "support", "supports") + ", " +
         count_text(m.loads.size() + m.link_loads.size(), "load", "loads") + ", " +
         (m.load_cases.empty()
              ? ""
              : count_text(m.load_cases.size(), "load case", "load cases") + ", ") +
         count_text(m.end_effectors.size(), "end effector", "end effectors") + ">";
}

// ---- argument conversion -----------------------------------------------------------------

LinkFrame link_frame(const std::string& frame, const std::string& link) {
  if (frame == "global") return LinkFrame::global;
  if (frame == "local") return LinkFrame::local;
  throw UsageError("link '" + link + "': frame '" + frame + "': expected \"global\" or \"local\"");
}

std::optional<Vec3> optional_vec3(const py::object& value, const std::string& what) {
  if (value.is_none()) return std::nullopt;
  return to_vec3(value, what);
}

std::optional<std::string> optional_name(const py::object& value, const std::string& what) {
  if (value.is_none()) return std::nullopt;
  if (!py::isinstance<py::str>(value))
    throw UsageError(what + ": expected a link name (str) or None");
  return value.cast<std::string>();
}

Connection make_connection(const Kinematics& kinematics, const py::object& stiffness,
                           const py::object& preload, bool actuated) {
  Connection c;
  c.kinematics = kinematics;
  const long p = free_direction_count(kinematics);
  if (!stiffness.is_none()) c.stiffness = to_matrix(stiffness, "Connection stiffness", p, p);
  if (!preload.is_none()) c.preload = to_vector(preload, "Connection preload", p);
  c.is_actuated = actuated;
  return c;
}

Section with_shear_areas(Section s, const std::optional<double>& Asy,
                         const std::optional<double>& Asz) {
  s.Asy = Asy;
  s.Asz = Asz;
  return s;
}

template <class Link>
void set_zref(Link& kind, const py::object& zref, const std::string& name) {
  kind.zref = optional_vec3(zref, "link '" + name + "': zref");
}

AnalysisMode to_mode(const py::object& mode) {
  if (py::isinstance<AnalysisMode>(mode)) return mode.cast<AnalysisMode>();
  if (py::isinstance<py::str>(mode))
    if (const auto parsed = analysis_mode_from_string(mode.cast<std::string>())) return *parsed;
  throw UsageError("analysis mode " + py::repr(mode).cast<std::string>() +
                   ": expected \"linear\" or \"loaded\" (or an AnalysisMode)");
}

// A load along a link from Python: a DistributedLinkLoad or a PointLinkLoad.
LinkLoad make_link_load(std::string link, const py::object& load) {
  if (py::isinstance<DistributedLinkLoad>(load))
    return LinkLoad{std::move(link), load.cast<DistributedLinkLoad>(), {}};
  if (py::isinstance<PointLinkLoad>(load))
    return LinkLoad{std::move(link), load.cast<PointLinkLoad>(), {}};
  throw UsageError("load along link '" + link +
                   "': expected a DistributedLinkLoad or a PointLinkLoad, got " +
                   py::repr(load).cast<std::string>());
}

Load make_load(std::string at, py::object link, py::object wrench) {
  // (at, wrench) reads as well as (at, link, wrench), as Model.add_load takes it.
  if (wrench.is_none() && !link.is_none() && !py::isinstance<py::str>(link))
    std::swap(link, wrench);
  if (wrench.is_none()) throw UsageError("load at '" + at + "': no wrench given");
  Load load;
  load.link = optional_name(link, "load at '" + at + "': link");
  load.wrench = to_vec6(wrench, "load at '" + at + "': wrench");
  load.at = std::move(at);
  return load;
}

py::object optional_vec3_array(const std::optional<Vec3>& value) {
  return to_optional_array(value);
}

}  // namespace

void bind_model(py::module_& m) {
  py::class_<Material>(m, "Material",
                       "An isotropic material: Young's modulus E (Pa) and exactly one of "
                       "Poisson's ratio nu or the shear modulus G (Pa).")
      .def(py::init([](double E, std::optional<double> nu, std::optional<double> G,
                       std::optional<double> density) {
             return Material{E, nu, G, density};
           }),
           py::arg("E"), py::arg("nu") = py::none(), py::arg("G") = py::none(), py::kw_only(),
           py::arg("density") = py::none())
      .def_readwrite("E", &Material::E)
      .def_readwrite("nu", &Material::nu)
      .def_readwrite("G", &Material::G)
      .def_readwrite("density", &Material::density,
                     "kg/m³, or None: a beam of this material weighs density·A·g per metre "
                     "under a load case's gravity.")
      .def("__repr__", [](const Material& mat) {
        std::ostringstream out;
        out << "Material(E=" << mat.E;
        if (mat.nu) out << ", nu=" << *mat.nu;
        if (mat.G) out << ", G=" << *mat.G;
        if (mat.density) out << ", density=" << *mat.density;
        return out.str() + ")";
      });

  py::enum_<AnalysisMode>(m, "AnalysisMode",
                          "The linear analysis at the unloaded pose, or the loaded mode: each "
                          "load case's equilibrium in the deformed geometry.")
      .value("linear", AnalysisMode::linear)
      .value("loaded", AnalysisMode::loaded);

  py::class_<DistributedLinkLoad>(
      m, "DistributedLinkLoad",
      "A dead load along a link, global axes: a force per metre of undeformed length (N/m), "
      "from `from_` at the link's from end varying linearly to `to` at its to end (uniform where "
      "`to` is left out).")
      .def(py::init([](py::object from, py::object to) {
             const Vec3 start = to_vec3(from, "DistributedLinkLoad from_");
             return DistributedLinkLoad{
                 start, to.is_none() ? start : to_vec3(to, "DistributedLinkLoad to")};
           }),
           py::arg("from_"), py::arg("to") = py::none())
      .def_property(
          "from_", [](const DistributedLinkLoad& q) { return to_array(VecX(q.from)); },
          [](DistributedLinkLoad& q, py::object v) { q.from = to_vec3(v, "from_"); })
      .def_property(
          "to", [](const DistributedLinkLoad& q) { return to_array(VecX(q.to)); },
          [](DistributedLinkLoad& q, py::object v) { q.to = to_vec3(v, "to"); })
      .def("__repr__", [](const DistributedLinkLoad& q) {
        return "DistributedLinkLoad(from_=" + py::repr(list_of(q.from)).cast<std::string>() +
               ", to=" + py::repr(list_of(q.to)).cast<std::string>() + ")";
      });

  py::class_<PointLinkLoad>(
      m, "PointLinkLoad",
      "A force (N) and a moment (N·m), global axes, at `position`, a fraction of the link's "
      "length from its from end (0 to 1).")
      .def(py::init([](py::object force, py::object moment, double position) {
             return PointLinkLoad{
                 to_vec3(force, "PointLinkLoad force"),
                 moment.is_none() ? Vec3::Zero() : to_vec3(moment, "PointLinkLoad moment"),
                 position};
           }),
           py::arg("force"), py::arg("moment") = py::none(), py::kw_only(), py::arg("position"))
      .def_property(
          "force", [](const PointLinkLoad& p) { return to_array(VecX(p.force)); },
          [](PointLinkLoad& p, py::object v) { p.force = to_vec3(v, "force"); })
      .def_property(
          "moment", [](const PointLinkLoad& p) { return to_array(VecX(p.moment)); },
          [](PointLinkLoad& p, py::object v) { p.moment = to_vec3(v, "moment"); })
      .def_readwrite("position", &PointLinkLoad::position)
      .def("__repr__", [](const PointLinkLoad& p) {
        return "PointLinkLoad(force=" + py::repr(list_of(p.force)).cast<std::string>() +
               ", moment=" + py::repr(list_of(p.moment)).cast<std::string>() +
               ", position=" + py::repr(py::float_(p.position)).cast<std::string>() + ")";
      });

  py::class_<LinkLoad>(m, "LinkLoad",
                       "A load along the link named `link`: a DistributedLinkLoad or a "
                       "PointLinkLoad (`load`).")
      .def(py::init(&make_link_load), py::arg("link"), py::arg("load"))
      .def_readwrite("link", &LinkLoad::link)
      .def_readwrite("load", &LinkLoad::load)
      .def("__repr__", [](const LinkLoad& l) {
        return "LinkLoad(" + py::repr(py::str(l.link)).cast<std::string>() + ", " +
               py::repr(py::cast(l.load)).cast<std::string>() + ")";
      });

  py::class_<Load>(m, "Load",
                   "A wrench [Fx, Fy, Fz, Mx, My, Mz] (N, N·m; global axes, moment about `at`) "
                   "on the link end at point `at` (`link` names the link where several ends "
                   "meet there).")
      .def(py::init(&make_load), py::arg("at"), py::arg("link") = py::none(),
           py::arg("wrench") = py::none())
      .def_readwrite("at", &Load::at)
      .def_readwrite("link", &Load::link)
      .def_property(
          "wrench", [](const Load& l) { return to_array(VecX(l.wrench)); },
          [](Load& l, py::object v) { l.wrench = to_vec6(v, "wrench"); })
      .def_readonly("self_weight", &Load::self_weight)
      .def("__repr__", [](const Load& l) {
        return "Load(" + py::repr(py::str(l.at)).cast<std::string>() +
               (l.link ? ", link=" + py::repr(py::str(*l.link)).cast<std::string>() : "") +
               ", wrench=" + py::repr(list_of(l.wrench)).cast<std::string>() + ")";
      });

  py::class_<LoadCase>(
      m, "LoadCase",
      "A named set of loads (a model file's `load_cases:`): loads on points, loads along "
      "links and a gravity (m/s², global axes; the beams whose material has a density weigh).")
      .def(py::init([](std::string name, std::vector<Load> loads, std::vector<LinkLoad> link_loads,
                       py::object gravity) {
             LoadCase c;
             c.name = std::move(name);
             c.loads = std::move(loads);
             c.link_loads = std::move(link_loads);
             c.gravity = optional_vec3(gravity, "load case '" + c.name + "': gravity");
             return c;
           }),
           py::arg("name"), py::arg("loads") = std::vector<Load>{},
           py::arg("link_loads") = std::vector<LinkLoad>{}, py::kw_only(),
           py::arg("gravity") = py::none())
      .def_readwrite("name", &LoadCase::name)
      .def_readwrite("loads", &LoadCase::loads, "The loads on points (a copy: assign to change).")
      .def_readwrite("link_loads", &LoadCase::link_loads,
                     "The loads along links (a copy: assign to change).")
      .def_property(
          "gravity", [](const LoadCase& c) { return optional_vec3_array(c.gravity); },
          [](LoadCase& c, py::object g) {
            c.gravity = optional_vec3(g, "load case '" + c.name + "': gravity");
          },
          "m/s², global axes, or None.")
      .def(
          "add_load",
          [](LoadCase& c, std::string at, py::object link, py::object wrench) {
            c.loads.push_back(make_load(std::move(at), std::move(link), std::move(wrench)));
          },
          py::arg("at"), py::arg("link") = py::none(), py::arg("wrench") = py::none(),
          "As Model.add_load, in this case.")
      .def(
          "add_link_load",
          [](LoadCase& c, std::string link, const py::object& load) {
            c.link_loads.push_back(make_link_load(std::move(link), load));
          },
          py::arg("link"), py::arg("load"), "As Model.add_link_load, in this case.")
      .def("__repr__", [](const LoadCase& c) {
        return "<stiffmsa.LoadCase '" + c.name +
               "': " + count_text(c.loads.size() + c.link_loads.size(), "load", "loads") +
               (c.gravity ? ", gravity" : "") + ">";
      });

  py::class_<Section>(
      m, "Section",
      "A beam's cross-section, made by one of its shape constructors (m, m², m⁴): circle(D), "
      "tube(D, t), rect(b, h), rect_tube(b, h, t), generic(A, Iy, Iz, J). Asy and Asz override "
      "the shape's shear areas (Timoshenko beams).")
      .def_static(
          "circle",
          [](double D, std::optional<double> Asy, std::optional<double> Asz) {
            return with_shear_areas(Section::circle(D), Asy, Asz);
          },
          py::arg("D"), py::kw_only(), py::arg("Asy") = py::none(), py::arg("Asz") = py::none(),
          "A solid round bar of diameter D.")
      .def_static(
          "tube",
          [](double D, double t, std::optional<double> Asy, std::optional<double> Asz) {
            return with_shear_areas(Section::tube(D, t), Asy, Asz);
          },
          py::arg("D"), py::arg("t"), py::kw_only(), py::arg("Asy") = py::none(),
          py::arg("Asz") = py::none(), "A round tube of outer diameter D and wall thickness t.")
      .def_static(
          "rect",
          [](double b, double h, std::optional<double> Asy, std::optional<double> Asz) {
            return with_shear_areas(Section::rect(b, h), Asy, Asz);
          },
          py::arg("b"), py::arg("h"), py::kw_only(), py::arg("Asy") = py::none(),
          py::arg("Asz") = py::none(),
          "A solid rectangle, width b along the beam's local y and height h along its local z.")
      .def_static(
          "rect_tube",
          [](double b, double h, double t, std::optional<double> Asy, std::optional<double> Asz) {
            return with_shear_areas(Section::rect_tube(b, h, t), Asy, Asz);
          },
          py::arg("b"), py::arg("h"), py::arg("t"), py::kw_only(), py::arg("Asy") = py::none(),
          py::arg("Asz") = py::none(),
          "A rectangular box of outer width b, height h and wall thickness t.")
      .def_static(
          "generic",
          [](double A, double Iy, double Iz, double J, std::optional<double> Asy,
             std::optional<double> Asz) {
            return with_shear_areas(Section::generic(A, Iy, Iz, J), Asy, Asz);
          },
          py::arg("A"), py::arg("Iy"), py::arg("Iz"), py::arg("J"), py::kw_only(),
          py::arg("Asy") = py::none(), py::arg("Asz") = py::none(),
          "Any section by its area A, second moments Iy and Iz and torsion constant J.")
      .def_property_readonly("shape",
                             [](const Section& s) { return std::string(to_string(s.shape)); })
      .def_readwrite("D", &Section::D)
      .def_readwrite("t", &Section::t)
      .def_readwrite("b", &Section::b)
      .def_readwrite("h", &Section::h)
      .def_readwrite("A", &Section::A)
      .def_readwrite("Iy", &Section::Iy)
      .def_readwrite("Iz", &Section::Iz)
      .def_readwrite("J", &Section::J)
      .def_readwrite("Asy", &Section::Asy)
      .def_readwrite("Asz", &Section::Asz)
      .def("__repr__", [](const Section& s) {
        return "Section(" + py::repr(section_dict(s)).cast<std::string>() + ")";
      });

  py::class_<Kinematics>(
      m, "Kinematics",
      "The free directions of a joint or support, by type (docs/model-format.md, joints): "
      "rigid(), revolute(axis), prismatic(axis), cylindrical(axis), universal(a, b), "
      "spherical(), planar(normal), custom(rows).")
      .def_static("rigid", &Kinematics::rigid, "No free direction: a weld.")
      .def_static(
          "revolute",
          [](py::object axis) { return Kinematics::revolute(to_vec3(axis, "revolute axis")); },
          py::arg("axis"), "Free to turn about `axis`.")
      .def_static(
          "prismatic",
          [](py::object axis) { return Kinematics::prismatic(to_vec3(axis, "prismatic axis")); },
          py::arg("axis"), "Free to slide along `axis`.")
      .def_static(
          "cylindrical",
          [](py::object axis) {
            return Kinematics::cylindrical(to_vec3(axis, "cylindrical axis"));
          },
          py::arg("axis"), "Free to slide along and turn about `axis`.")
      .def_static(
          "universal",
          [](py::object a, py::object b) {
            return Kinematics::universal(to_vec3(a, "universal axis a"),
                                         to_vec3(b, "universal axis b"));
          },
          py::arg("a"), py::arg("b"), "Free to turn about `a`, then about `b`.")
      .def_static("spherical", &Kinematics::spherical, "Free to turn about every axis.")
      .def_static(
          "planar",
          [](py::object normal) { return Kinematics::planar(to_vec3(normal, "planar normal")); },
          py::arg("normal"), "Free to slide in the plane of `normal` and turn about it.")
      .def_static(
          "custom",
          [](py::object rows) {
            const MatX matrix = to_matrix(rows, "custom free directions", std::nullopt, 6);
            std::vector<Vec6> free;
            for (Eigen::Index r = 0; r < matrix.rows(); ++r)
              free.push_back(matrix.row(r).transpose());
            return Kinematics::custom(std::move(free));
          },
          py::arg("rows"),
          "Free along the given 6-vectors [dx, dy, dz, rx, ry, rz], used as written.")
      .def_property_readonly("type",
                             [](const Kinematics& k) { return std::string(to_string(k.type)); })
      .def_property_readonly(
          "free_direction_count", &free_direction_count,
          "p: the number of free directions (the size of stiffness and preload).")
      .def("__repr__", [](const Kinematics& k) {
        return "<stiffmsa.Kinematics " + std::string(to_string(k.type)) + ", " +
               std::to_string(free_direction_count(k)) + " free directions>";
      });

  py::class_<Connection>(
      m, "Connection",
      "What a joint or support does along its free directions: passive (neither stiffness nor "
      "actuated), elastic (`stiffness`, p×p, or one number where p = 1), preloaded (`preload`, p "
      "numbers) and/or actuated (locked without a stiffness, its effort reported). The default "
      "is rigid.")
      .def(py::init(&make_connection), py::arg("kinematics") = Kinematics::rigid(),
           py::arg("stiffness") = py::none(), py::arg("preload") = py::none(),
           py::arg("actuated") = false)
      .def_readonly("kinematics", &Connection::kinematics)
      .def_property_readonly("stiffness",
                             [](const Connection& c) { return to_optional_array(c.stiffness); })
      .def_property_readonly("preload",
                             [](const Connection& c) { return to_optional_array(c.preload); })
      .def_static("rigid", &Connection::rigid, "A weld: no free direction (the default).")
      .def_static(
          "passive", [](const Kinematics& k) { return Connection::passive(k); },
          py::arg("kinematics"),
          "Free along the kinematics' directions, neither resisted nor driven.")
      .def_static(
          "elastic",
          [](const Kinematics& k, py::object stiffness) {
            return make_connection(k, stiffness, py::none(), false);
          },
          py::arg("kinematics"), py::arg("stiffness"),
          "A spring on the free directions: p×p, or one number where p = 1.")
      // Python keeps `actuated` for the property, so the factory is `actuator`.
      .def_static(
          "actuator",
          [](const Kinematics& k, py::object stiffness) {
            return make_connection(k, stiffness, py::none(), true);
          },
          py::arg("kinematics"), py::arg("stiffness") = py::none(),
          "A drive: locked along the free directions (its effort reported), or yielding as a "
          "spring "
          "with a stiffness (p×p, or one number where p = 1).")
      .def(
          "preloaded",
          [](const Connection& c, py::object preload) {
            Connection loaded = c;
            loaded.preload =
                to_vector(preload, "Connection preload", free_direction_count(c.kinematics));
            return loaded;
          },
          py::arg("preload"), "The same connection with a preload: p numbers (one where p = 1).")
      .def_readonly("actuated", &Connection::is_actuated)
      .def("__repr__", [](const Connection& c) {
        return "<stiffmsa.Connection " + std::string(to_string(c.kinematics.type)) +
               (c.stiffness ? ", elastic" : "") + (c.preload ? ", preloaded" : "") +
               (c.is_actuated ? ", actuated" : "") + ">";
      });

  py::class_<Model>(
      m, "Model",
      "A manipulator as points, links, joints, supports, loads and end effectors, named by "
      "strings. Build one with the add_* verbs (the same as the C++ Model's and a model file's "
      "sections) or read one with load_model(); solve it with solve().")
      .def(py::init([](std::string name) {
             Model model;
             model.name = std::move(name);
             return model;
           }),
           py::arg("name") = "model")
      .def_readwrite("name", &Model::name)
      .def_property(
          "accept_idle_motions",
          [](const Model& model) { return model.options.accept_idle_motions; },
          [](Model& model, bool accept) { model.options.accept_idle_motions = accept; },
          "The model's own `options: {accept_idle_motions}`.")
      .def_property(
          "mode", [](const Model& model) { return model.options.mode; },
          [](Model& model, const py::object& mode) { model.options.mode = to_mode(mode); },
          "The model's own analysis mode (`analysis: {mode}`): AnalysisMode.linear or .loaded "
          "(\"linear\" or \"loaded\" are taken too); solve(mode=...) overrides it.")
      .def_property(
          "load_steps", [](const Model& model) { return model.options.load_steps; },
          [](Model& model, std::optional<int> steps) { model.options.load_steps = steps; },
          "The loaded mode's number of load steps (`analysis: {load_steps}`), or None.")
      .def_property(
          "gravity", [](const Model& model) { return optional_vec3_array(model.gravity); },
          [](Model& model, py::object g) { model.gravity = optional_vec3(g, "model gravity"); },
          "The unnamed load case's gravity (m/s², global axes), or None.")
      .def_property_readonly(
          "link_loads", [](const Model& model) { return model.link_loads; },
          "The unnamed case's loads along links (copies), in model order.")
      .def_property_readonly(
          "load_cases", [](const Model& model) { return model.load_cases; },
          "The named load cases (copies), in model order.")
      .def_property_readonly(
          "source_file", [](const Model& model) { return model.source_file; },
          "The file the model was read from ('' for a model built in code).")
      .def(
          "add_point",
          [](Model& model, std::string name, py::object position) {
            model.add_point(name, to_vec3(position, "point '" + name + "': position"));
          },
          py::arg("name"), py::arg("position"),
          "A named point at `position` [x, y, z] (m, global axes).")
      .def(
          "add_material",
          [](Model& model, std::string name, const Material& material) {
            model.add_material(std::move(name), material);
          },
          py::arg("name"), py::arg("material"),
          "A named material, for add_beam to refer to by name.")
      .def(
          "add_section",
          [](Model& model, std::string name, const Section& section) {
            model.add_section(std::move(name), section);
          },
          py::arg("name"), py::arg("section"), "A named section, for add_beam to refer to by name.")
      .def_property_readonly(
          "materials",
          [](const Model& model) {
            py::dict named;
            for (const auto& [name, material] : model.materials)
              named[py::str(name)] = py::cast(material);
            return named;
          },
          "The named materials (add_material), by name.")
      .def_property_readonly(
          "sections",
          [](const Model& model) {
            py::dict named;
            for (const auto& [name, section] : model.sections)
              named[py::str(name)] = py::cast(section);
            return named;
          },
          "The named sections (add_section), by name.")
      .def(
          "add_beam",
          [](Model& model, std::string name, std::string from, std::string to, py::object material,
             py::object section, bool shear, py::object zref) {
            // By name (add_material, add_section) or by value.
            const Material m = py::isinstance<py::str>(material)
                                   ? model.material(material.cast<std::string>())
                                   : material.cast<Material>();
            const Section s = py::isinstance<py::str>(section)
                                  ? model.section(section.cast<std::string>())
                                  : section.cast<Section>();
            auto& kind = std::get<BeamLink>(model.link(model.add_beam(name, from, to, m, s)).kind);
            kind.shear = shear;
            set_zref(kind, zref, name);
          },
          py::arg("name"), py::arg("from_"), py::arg("to"), py::arg("material"), py::arg("section"),
          py::kw_only(), py::arg("shear") = false, py::arg("zref") = py::none(),
          "A flexible link (a 3-D beam) between points `from_` and `to`; `shear=True` makes it a "
          "Timoshenko "
          "beam, `zref` fixes the orientation of its section (default global Z).")
      .def(
          "add_rigid_link",
          [](Model& model, std::string name, std::string from, std::string to) {
            model.add_rigid_link(std::move(name), std::move(from), std::move(to));
          },
          py::arg("name"), py::arg("from_"), py::arg("to"), "A rigid link between two points.")
      .def(
          "add_matrix_link",
          [](Model& model, std::string name, std::string from, std::string to, py::object K,
             const std::string& frame, py::object zref) {
            const Mat12 stiffness = to_matrix(K, "link '" + name + "': K", 12, 12);
            auto& kind = std::get<MatrixLink>(
                model
                    .link(model.add_matrix_link(name, from, to, stiffness, link_frame(frame, name)))
                    .kind);
            set_zref(kind, zref, name);
          },
          py::arg("name"), py::arg("from_"), py::arg("to"), py::arg("K"),
          py::arg("frame") = "global", py::kw_only(), py::arg("zref") = py::none(),
          "A CAD-based link: its 12×12 free-free stiffness K over [Δt_from; Δt_to], in global axes "
          "or "
          "(frame=\"local\") in the link's beam axes.")
      .def(
          "add_compliance_link",
          [](Model& model, std::string name, std::string from, std::string to, py::object C,
             const std::string& frame, py::object zref) {
            const Mat6 compliance = to_matrix(C, "link '" + name + "': C", 6, 6);
            auto& kind = std::get<ComplianceLink>(
                model
                    .link(model.add_compliance_link(name, from, to, compliance,
                                                    link_frame(frame, name)))
                    .kind);
            set_zref(kind, zref, name);
          },
          py::arg("name"), py::arg("from_"), py::arg("to"), py::arg("C"),
          py::arg("frame") = "global", py::kw_only(), py::arg("zref") = py::none(),
          "A CAD-based link: the 6×6 compliance of end `to` with end `from` clamped.")
      .def(
          "add_joint",
          [](Model& model, std::string name, std::string at, py::object links,
             const Connection& connection) {
            model.add_joint(name, std::move(at), to_names(links, "joint '" + name + "': links"),
                            connection);
          },
          py::arg("name"), py::arg("at"), py::arg("links"),
          py::arg("connection") = Connection::rigid(),
          "A joint at point `at` between the listed link ends (the first is the one its wrench is "
          "reported "
          "on); rigid unless `connection` says otherwise.")
      .def(
          "add_support",
          [](Model& model, std::string name, std::string at, py::object links,
             const Connection& connection, py::object displacement) {
            const auto support = model.add_support(
                name, std::move(at), to_names(links, "support '" + name + "': links"), connection);
            if (!displacement.is_none())
              model.support(support).displacement =
                  to_vec6(displacement, "support '" + name + "': displacement");
          },
          py::arg("name"), py::arg("at"), py::arg("links") = py::list(),
          py::arg("connection") = Connection::rigid(), py::kw_only(),
          py::arg("displacement") = py::none(),
          "A support connecting link ends at point `at` to the ground (every link end there when "
          "`links` is "
          "empty); rigid unless `connection` says otherwise. `displacement` [dx, dy, dz, rx, ry, "
          "rz] (m, rad; global axes) is a settlement of the directions it holds, in every load "
          "case.")
      .def(
          "add_load",
          [](Model& model, std::string at, py::object link, py::object wrench) {
            // add_load(at, wrench) reads as well as the C++ order add_load(at, link, wrench).
            if (wrench.is_none() && !link.is_none() && !py::isinstance<py::str>(link))
              std::swap(link, wrench);
            if (wrench.is_none()) throw UsageError("load at '" + at + "': no wrench given");
            model.add_load(at, optional_name(link, "load at '" + at + "': link"),
                           to_vec6(wrench, "load at '" + at + "': wrench"));
          },
          py::arg("at"), py::arg("link") = py::none(), py::arg("wrench") = py::none(),
          "A wrench [Fx, Fy, Fz, Mx, My, Mz] (N, N·m; global axes, moment about `at`) on the link "
          "end at point "
          "`at` (name the link where several ends meet there). add_load(at, wrench) is accepted "
          "too.")
      .def(
          "add_link_load",
          [](Model& model, std::string link, const py::object& load) {
            model.link_loads.push_back(make_link_load(std::move(link), load));
          },
          py::arg("link"), py::arg("load"),
          "A load along the link (the unnamed case): a DistributedLinkLoad or a PointLinkLoad.")
      .def(
          "add_load_case", [](Model& model, const LoadCase& c) { model.add_load_case(c); },
          py::arg("load_case"), "A named load case (a copy of it).")
      .def(
          "add_end_effector",
          [](Model& model, std::string name, std::string at, py::object link) {
            model.add_end_effector(name, std::move(at),
                                   optional_name(link, "end effector '" + name + "': link"));
          },
          py::arg("name"), py::arg("at"), py::arg("link") = py::none(),
          "A point whose Cartesian compliance and stiffness the solve reports.")
      .def("to_dict", &model_dict,
           "The model as plain Python data (names, numbers and lists, shaped like a model file's "
           "sections), "
           "without where it came from: two models that solve alike have equal dicts.")
      .def("__eq__",
           [](const Model& a, const Model& b) { return model_dict(a).equal(model_dict(b)); })
      .def(
          "copy", [](const Model& model) { return Model(model); }, "An independent copy.")
      .def("__copy__", [](const Model& model) { return Model(model); })
      .def(
          "__deepcopy__", [](const Model& model, py::dict) { return Model(model); },
          py::arg("memo"))
      .def("__repr__", &model_repr);

  m.def(
      "load_model",
      [](const std::filesystem::path& path, const std::map<std::string, double>& values) {
        if (values.empty()) return load_model(path);
        const ModelFamily family = load_model_family(path, {}, values);
        return family.build(family.default_values());
      },
      py::arg("path"), py::arg("values"));

  py::class_<SystemSize>(m, "SystemSize",
                         "The size of the assembled system: unknowns, equations, nonzeros.")
      .def_readonly("unknowns", &SystemSize::unknowns)
      .def_readonly("equations", &SystemSize::equations)
      .def_readonly("nonzeros", &SystemSize::nonzeros)
      .def("__repr__", [](const SystemSize& s) {
        return "SystemSize(unknowns=" + std::to_string(s.unknowns) +
               ", equations=" + std::to_string(s.equations) +
               ", nonzeros=" + std::to_string(s.nonzeros) + ")";
      });
  m.def("check", &check, py::arg("model"),
        "Validates the model and assembles its system without solving; returns its SystemSize. "
        "Raises "
        "InputError listing every defect.");
}

}  // namespace stiffmsa::python
