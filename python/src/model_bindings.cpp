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

py::dict model_dict(const Model& model) {
  py::dict d, points, links, joints, supports, end_effectors;
  py::list loads;
  d["name"] = model.name;
  d["options"] = py::dict(py::arg("accept_idle_motions") = model.options.accept_idle_motions);
  for (const auto& p : model.points) points[py::str(p.name)] = list_of(p.position);
  for (const auto& l : model.links) links[py::str(l.name)] = link_dict(l);
  for (const auto& j : model.joints)
    joints[py::str(j.name)] = connection_dict(j.at, j.links, j.connection);
  for (const auto& s : model.supports)
    supports[py::str(s.name)] = connection_dict(s.at, s.links, s.connection);
  for (const auto& l : model.loads)
    loads.append(py::dict(py::arg("at") = l.at, py::arg("link") = optional_of(l.link),
                          py::arg("wrench") = list_of(l.wrench)));
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
         count_text(m.loads.size(), "load", "loads") + ", " +
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

}  // namespace

void bind_model(py::module_& m) {
  py::class_<Material>(m, "Material",
                       "An isotropic material: Young's modulus E (Pa) and exactly one of "
                       "Poisson's ratio nu or the shear modulus G (Pa).")
      .def(py::init([](double E, std::optional<double> nu, std::optional<double> G) {
             return Material{E, nu, G, std::nullopt};
           }),
           py::arg("E"), py::arg("nu") = py::none(), py::arg("G") = py::none())
      .def_readwrite("E", &Material::E)
      .def_readwrite("nu", &Material::nu)
      .def_readwrite("G", &Material::G)
      .def("__repr__", [](const Material& mat) {
        std::ostringstream out;
        out << "Material(E=" << mat.E;
        if (mat.nu) out << ", nu=" << *mat.nu;
        if (mat.G) out << ", G=" << *mat.G;
        return out.str() + ")";
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
             const Connection& connection) {
            model.add_support(name, std::move(at), to_names(links, "support '" + name + "': links"),
                              connection);
          },
          py::arg("name"), py::arg("at"), py::arg("links") = py::list(),
          py::arg("connection") = Connection::rigid(),
          "A support connecting link ends at point `at` to the ground (every link end there when "
          "`links` is "
          "empty); rigid unless `connection` says otherwise.")
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
