#pragma once
// The rules for a material's and a section's values (sections.md), shared by validation, which
// checks them on each beam, and the model file loader, which checks each named material and
// section once, where it is defined.
#include <span>
#include <string>
#include <vector>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// The dimensions each section shape is given by: the keys a model file uses and the values
// validation checks are one table.
struct SectionDimension {
  const char* key;
  double Section::*value;
};

inline std::span<const SectionDimension> section_dimensions(SectionShape shape) {
  static constexpr SectionDimension circle[] = {{"D", &Section::D}};
  static constexpr SectionDimension tube[] = {{"D", &Section::D}, {"t", &Section::t}};
  static constexpr SectionDimension rect[] = {{"b", &Section::b}, {"h", &Section::h}};
  static constexpr SectionDimension rect_tube[] = {
      {"b", &Section::b}, {"h", &Section::h}, {"t", &Section::t}};
  static constexpr SectionDimension generic[] = {
      {"A", &Section::A}, {"Iy", &Section::Iy}, {"Iz", &Section::Iz}, {"J", &Section::J}};
  switch (shape) {
    case SectionShape::circle: return circle;
    case SectionShape::tube: return tube;
    case SectionShape::rect: return rect;
    case SectionShape::rect_tube: return rect_tube;
    case SectionShape::generic: return generic;
  }
  return {};
}

// A defect of one value: its key within the material or section ("" for the whole) and what
// is wrong with it.
struct ValueDefect {
  std::string key;
  std::string message;
};

// E > 0, exactly one of nu in (-1, 0.5) or G > 0.
std::vector<ValueDefect> material_defects(const Material& m);

// The shape's dimensions and any shear areas positive, walls thinner than half the outer size.
std::vector<ValueDefect> section_defects(const Section& s);

class ModelIndex;
// stiffmsa::find_implausible_values with the model's index already built (a sweep checks
// every pose).
std::vector<Diagnostic> find_implausible_values(const Model& model, const ModelIndex& index);

}  // namespace stiffmsa::detail
