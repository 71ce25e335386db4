#pragma once
// What a Structure compiles from its model once: the name index and the topology every pose
// shares, and the names of its value slots.
#include <mutex>
#include <string>
#include <vector>

#include "model/link_ends.hpp"
#include "model/topology.hpp"
#include "stiffmsa/structure.hpp"

namespace stiffmsa {

struct Structure::Impl {
  explicit Impl(Model validated);
  // `other` with these values as its defaults.
  Impl(const Impl& other, std::span<const double> values);

  Model model;               // numbers at the defaults
  detail::ModelIndex index;  // of `model`; its lookups give positions, valid in every pose
  detail::Topology topology;
  std::size_t value_count = 0;
  // Made at the first request: a large frame solved once needs no name per number.
  mutable std::once_flag named;
  mutable std::vector<std::string> slot_names;
  const std::vector<std::string>& names() const;
};

namespace detail {
// Whether two models have one structure: the same entities in the same order with the same
// names, kinds, connections and optional numbers (Structure::values_of's test).
bool same_structure(const Model& a, const Model& b);
}  // namespace detail

}  // namespace stiffmsa
