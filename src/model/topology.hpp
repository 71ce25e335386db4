#pragma once
// How the link ends of a model are connected: which joint, support, default rigid connection or
// free end holds each link end, and where loads and end effectors sit. Depends on names,
// connectivity and the order of the points, never on numbers: a Structure's part, built once.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "model/link_ends.hpp"
#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

struct ConnectionGroup {
  enum class Kind { joint, support, rigid_connection, free_end };
  Kind kind = Kind::free_end;
  int source = -1;  // index into model.joints / model.supports
  std::string point;
  std::vector<int> ends;  // link end ids; the first is "end 1"
  bool operator==(const ConnectionGroup&) const = default;
};

struct Topology {
  int link_count = 0;
  std::vector<ConnectionGroup> groups;
  std::vector<int> group_of_end;     // per link end id
  std::vector<int> end_points;       // per link end id: its point, an index into model.points
  std::vector<int> load_ends;        // per model.loads
  std::vector<int> link_load_links;  // per model.link_loads: the link's index
  // Per model.load_cases: per load of the case, its link end, and per link load, its link.
  std::vector<std::vector<int>> case_load_ends;
  std::vector<std::vector<int>> case_link_load_links;
  std::vector<int> effector_ends;  // per model.end_effectors

  int end_count() const { return 2 * link_count; }
  Eigen::Index unknowns() const { return 12 * static_cast<Eigen::Index>(end_count()); }
  bool operator==(const Topology&) const = default;
};

// The topology of a validated model. Throws InputError where the connection rules are broken.
Topology build_topology(const Model& model);
Topology build_topology(const Model& model, const ModelIndex& index);

}  // namespace stiffmsa::detail
