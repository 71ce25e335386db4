#pragma once
// Every number a model holds, visited in one fixed order: the value slots of a Structure
// (stiffmsa/structure.hpp). A number's place in this order is its slot; its SlotName says
// which key of which entity it is (`links.upper.material.E`). Two models of the same structure
// (same entities, kinds and optional values present) visit the same numbers in the same order.
#include <algorithm>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// Where a number sits, for messages; made into text only when a name is asked for.
struct SlotName {
  const char* collection = "";          // "points", "links", ...
  const std::string* entity = nullptr;  // its name; loads have none and are numbered
  std::size_t entity_index = 0;
  bool numbered = true;  // false for a value of the model itself (`gravity`): no entity part
  // A numbered part within the entity, as a load case's `loads[0]`; none where nullptr.
  const char* part = nullptr;
  std::size_t part_index = 0;
  const char* key = nullptr;     // within the entity; none for a point's coordinates
  int rows = 0;                  // 0 for a scalar, 1 for a vector, 2 for a matrix
  Eigen::Index matrix_rows = 0;  // of a matrix
  Eigen::Index element = 0;      // column-major within the matrix or vector

  std::string str() const {
    std::string text = collection;
    if (entity)
      text += "." + *entity;
    else if (numbered)
      text += "[" + std::to_string(entity_index) + "]";
    if (part) text += std::string(".") + part + "[" + std::to_string(part_index) + "]";
    if (key) text += std::string(".") + key;
    if (rows == 1)
      text += "[" + std::to_string(element) + "]";
    else if (rows > 1)
      text += "[" + std::to_string(element % matrix_rows) + "][" +
              std::to_string(element / matrix_rows) + "]";
    return text;
  }
};

// `visit(double& value, const SlotName& name)` for every number of the model in slot order.
template <class ModelRef, class Visit>
void for_each_named_number(ModelRef& model, Visit&& visit) {
  SlotName at;
  const auto scalar = [&](auto& value, const char* key) {
    at.key = key;
    at.rows = 0;
    at.element = 0;
    visit(value, at);
  };
  const auto each = [&](auto& dense, const char* key) {
    at.key = key;
    // A vector's entries are numbered once, a matrix's by row and column (a 1×1 spring too).
    at.rows = std::decay_t<decltype(dense)>::ColsAtCompileTime == 1 ? 1 : 2;
    at.matrix_rows = dense.rows();
    for (Eigen::Index i = 0; i < dense.size(); ++i) {
      at.element = i;
      visit(dense.data()[i], at);
    }
  };
  const auto maybe = [&](auto& optional, const char* key) {
    if (optional) scalar(*optional, key);
  };
  const auto maybe_dense = [&](auto& optional, const char* key) {
    if (optional) each(*optional, key);
  };
  const auto entity = [&](const char* collection, const std::string* name, std::size_t index) {
    at.collection = collection;
    at.entity = name;
    at.entity_index = index;
    at.numbered = true;
    at.part = nullptr;
  };
  const auto link_load = [&](auto& load) {
    if (auto* distributed = std::get_if<DistributedLinkLoad>(&load.load)) {
      each(distributed->from, "distributed.from");
      each(distributed->to, "distributed.to");
    } else if (auto* point = std::get_if<PointLinkLoad>(&load.load)) {
      each(point->force, "force");
      each(point->moment, "moment");
      scalar(point->position, "position");
    }
  };
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    auto& point = model.points[i];
    entity("points", &point.name, i);
    each(point.position, nullptr);
  }
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    auto& link = model.links[i];
    entity("links", &link.name, i);
    if (auto* beam = std::get_if<BeamLink>(&link.kind)) {
      scalar(beam->material.E, "material.E");
      maybe(beam->material.nu, "material.nu");
      maybe(beam->material.G, "material.G");
      maybe(beam->material.density, "material.density");
      auto& s = beam->section;
      scalar(s.D, "section.D");
      scalar(s.t, "section.t");
      scalar(s.b, "section.b");
      scalar(s.h, "section.h");
      scalar(s.A, "section.A");
      scalar(s.Iy, "section.Iy");
      scalar(s.Iz, "section.Iz");
      scalar(s.J, "section.J");
      maybe(s.Asy, "section.Asy");
      maybe(s.Asz, "section.Asz");
      maybe_dense(beam->zref, "zref");
    } else if (auto* matrix = std::get_if<MatrixLink>(&link.kind)) {
      each(matrix->K, "K");
      maybe_dense(matrix->zref, "zref");
    } else if (auto* compliance = std::get_if<ComplianceLink>(&link.kind)) {
      each(compliance->C, "C");
      maybe_dense(compliance->zref, "zref");
    }
  }
  const auto connection = [&](auto& c) {
    const bool universal = c.kinematics.type == JointType::universal;
    each(c.kinematics.axis, universal ? "axes[0]" : "axis");
    each(c.kinematics.axis_b, universal ? "axes[1]" : "axis_b");
    each(c.kinematics.normal, "normal");
    // A custom joint has at most 6 free directions (validation refuses more).
    static constexpr const char* free_row[] = {"free[0]", "free[1]", "free[2]",
                                               "free[3]", "free[4]", "free[5]"};
    for (std::size_t r = 0; r < c.kinematics.free_rows.size(); ++r)
      each(c.kinematics.free_rows[r], r < 6 ? free_row[r] : "free[>5]");
    maybe_dense(c.stiffness, "stiffness");
    maybe_dense(c.preload, "preload");
  };
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    entity("joints", &model.joints[i].name, i);
    connection(model.joints[i].connection);
  }
  for (std::size_t i = 0; i < model.supports.size(); ++i) {
    entity("supports", &model.supports[i].name, i);
    connection(model.supports[i].connection);
    maybe_dense(model.supports[i].displacement, "displacement");
  }
  for (std::size_t i = 0; i < model.loads.size(); ++i) {
    entity("loads", nullptr, i);
    each(model.loads[i].wrench, "wrench");
  }
  for (std::size_t i = 0; i < model.link_loads.size(); ++i) {
    entity("link_loads", nullptr, i);
    link_load(model.link_loads[i]);
  }
  if (model.gravity) {
    entity("gravity", nullptr, 0);
    at.numbered = false;
    each(*model.gravity, nullptr);
  }
  for (std::size_t c = 0; c < model.load_cases.size(); ++c) {
    auto& load_case = model.load_cases[c];
    entity("load_cases", &load_case.name, c);
    for (std::size_t i = 0; i < load_case.loads.size(); ++i) {
      at.part = "loads";
      at.part_index = i;
      each(load_case.loads[i].wrench, "wrench");
    }
    for (std::size_t i = 0; i < load_case.link_loads.size(); ++i) {
      at.part = "link_loads";
      at.part_index = i;
      link_load(load_case.link_loads[i]);
    }
    at.part = nullptr;
    maybe_dense(load_case.gravity, "gravity");
  }
  for (std::size_t i = 0; i < model.end_effectors.size(); ++i) {
    entity("end_effectors", &model.end_effectors[i].name, i);
    maybe_dense(model.end_effectors[i].axes, "axes");
  }
}

// `visit(double& value)` for every number of the model in slot order.
template <class ModelRef, class Visit>
void for_each_number(ModelRef& model, Visit&& visit) {
  for_each_named_number(model, [&](auto& value, const SlotName&) { visit(value); });
}

}  // namespace stiffmsa::detail
