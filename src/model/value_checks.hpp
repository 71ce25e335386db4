#pragma once
// The rules for a material's and a section's values (sections.md), shared by validation, which
// checks them on each beam, and the model file loader, which checks each named material and
// section once, where it is defined.
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

inline std::vector<SectionDimension> section_dimensions(SectionShape shape) {
  switch (shape) {
    case SectionShape::circle:
      return {{"D", &Section::D}};
    case SectionShape::tube:
      return {{"D", &Section::D}, {"t", &Section::t}};
    case SectionShape::rect:
      return {{"b", &Section::b}, {"h", &Section::h}};
    case SectionShape::rect_tube:
      return {{"b", &Section::b}, {"h", &Section::h}, {"t", &Section::t}};
    case SectionShape::generic:
      return {{"A", &Section::A}, {"Iy", &Section::Iy}, {"Iz", &Section::Iz}, {"J", &Section::J}};
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

}  // namespace stiffmsa::detail
