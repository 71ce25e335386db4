#pragma once
// Every number a model holds, visited in one fixed order: how a parametric model's builder
// finds the numbers its expressions fill, and refills them for the next pose without reading
// the file again. Two models of the same structure (same entities, kinds and optional values
// present) visit the same numbers in the same order.
#include <optional>
#include <variant>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

template <class Visit>
void for_each_number(Model& model, Visit&& visit) {
  const auto each = [&](auto& dense) {
    for (Eigen::Index i = 0; i < dense.size(); ++i) visit(dense.data()[i]);
  };
  const auto maybe = [&](auto& optional) {
    if (optional) visit(*optional);
  };
  const auto maybe_dense = [&](auto& optional) {
    if (optional) each(*optional);
  };
  for (auto& point : model.points) each(point.position);
  for (auto& link : model.links) {
    if (auto* beam = std::get_if<BeamLink>(&link.kind)) {
      visit(beam->material.E);
      maybe(beam->material.nu);
      maybe(beam->material.G);
      Section& s = beam->section;
      for (double* dimension : {&s.D, &s.t, &s.b, &s.h, &s.A, &s.Iy, &s.Iz, &s.J}) visit(*dimension);
      maybe(s.Asy);
      maybe(s.Asz);
      maybe_dense(beam->zref);
    } else if (auto* matrix = std::get_if<MatrixLink>(&link.kind)) {
      each(matrix->K);
      maybe_dense(matrix->zref);
    } else if (auto* compliance = std::get_if<ComplianceLink>(&link.kind)) {
      each(compliance->C);
      maybe_dense(compliance->zref);
    }
  }
  const auto connection = [&](Connection& c) {
    each(c.kinematics.axis);
    each(c.kinematics.axis_b);
    each(c.kinematics.normal);
    for (auto& row : c.kinematics.free_rows) each(row);
    maybe_dense(c.stiffness);
    maybe_dense(c.preload);
  };
  for (auto& joint : model.joints) connection(joint.connection);
  for (auto& support : model.supports) connection(support.connection);
  for (auto& load : model.loads) each(load.wrench);
}

}  // namespace stiffmsa::detail
