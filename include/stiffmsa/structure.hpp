#pragma once
// A model split in two, as Pinocchio splits a robot's Model from its configuration q: the
// Structure is what a pose never changes (names, kinds, connectivity, topology, where each
// number goes), validated once and immutable; the values are every number the model holds
// (coordinates, axes, materials, sections, matrices, springs, preloads, loads) in one flat
// vector whose slots the structure names (`links.upper.material.E`). A Model, with its add_*
// verbs and the file it was read from, compiles into both; per pose only the values change,
// and only value checks run on them (docs/theory.md, "Structure and values").
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "stiffmsa/model.hpp"

namespace stiffmsa {

class Structure {
 public:
  // Validates the model (every defect, structural or of a value, throws InputError as
  // validate() does) and keeps its structure; its numbers are the structure's default values.
  explicit Structure(Model model);

  // The model the structure was compiled from: names, kinds, connectivity and the source
  // locations its diagnostics point at; its numbers are default_values().
  const Model& model() const;

  // One name per value slot, in slot order: "points.A[0]", "links.upper.material.E",
  // "joints.j1.stiffness[0][0]", "loads[0].wrench[2]".
  std::size_t value_count() const;
  const std::vector<std::string>& slot_names() const;
  std::optional<std::size_t> find_slot(std::string_view name) const;
  std::vector<double> default_values() const;

  // The values of a model of this structure. Throws InputError when the model's structure
  // differs (an entity added, renamed or reconnected, another kind, an optional number
  // given or left out): its numbers would fill other slots.
  std::vector<double> values_of(const Model& model) const;
  // The model with these values (value_count() of them) in place of the defaults; no checks.
  Model model_with(std::span<const double> values) const;
  // Writes the values into a model made by model_with() (or a copy of model()).
  void write_values(std::span<const double> values, Model& model) const;

  // The same structure with these values as its defaults (a Workspace's reference pose);
  // they are not checked.
  Structure with_default_values(std::span<const double> values) const;

  // The defects of these values alone (positive moduli, positive definite matrices, non-zero
  // and non-parallel axes, non-zero lengths, finite numbers), each at its key and the source
  // location of the structure's model; empty when the values are valid. Names and
  // connectivity are not checked again: the structure was validated when it was built.
  std::vector<Diagnostic> find_value_defects(std::span<const double> values) const;

  // Two structures are the same when they share their compiled form (copies of one another).
  bool operator==(const Structure& other) const { return impl_ == other.impl_; }

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<const Impl> impl_;
};

}  // namespace stiffmsa
