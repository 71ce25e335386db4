#include "model/topology.hpp"

#include <algorithm>
#include <utility>

#include "model/link_ends.hpp"

namespace stiffmsa::detail {

namespace {

[[noreturn]] void fail(const Origin& origin, std::string key_path, std::string message) {
  throw InputError(origin.location, std::move(key_path), std::move(message));
}

// The key path of a joint, support or end effector ("joints.A1"), spelt out only on failure.
struct EntityPath {
  const char* collection;
  const std::string& name;
  std::string str() const { return std::string(collection) + "." + name; }
};

std::vector<int> named_ends(const ModelIndex& index, const std::string& point,
                            const std::vector<std::string>& link_names, const Origin& origin,
                            const EntityPath& path) {
  std::vector<int> ends;
  if (link_names.empty()) {
    const auto at_point = index.ends_at(point);
    if (at_point.empty()) fail(origin, path.str(), "no link end is at point '" + point + "'");
    ends.reserve(at_point.size());
    for (const auto& e : at_point) ends.push_back(e.id());
    return ends;
  }
  ends.reserve(link_names.size());
  for (const auto& name : link_names) {
    std::string problem;
    const auto end = index.resolve(point, name, problem);
    if (!end) fail(origin, path.str() + ".links", problem);
    ends.push_back(end->id());
  }
  return ends;
}

template <class KeyPath>
int end_of(const ModelIndex& index, const std::string& point,
           const std::optional<std::string>& link, const Origin& origin, const KeyPath& key_path) {
  std::string problem;
  const auto end = index.resolve(point, link, problem);
  if (!end) fail(origin, key_path(), problem);
  return end->id();
}

}  // namespace

Topology build_topology(const Model& model) { return build_topology(model, ModelIndex(model)); }

Topology build_topology(const Model& model, const ModelIndex& index) {
  Topology t;
  t.link_count = static_cast<int>(model.links.size());
  t.group_of_end.assign(static_cast<std::size_t>(t.end_count()), -1);
  t.end_points.resize(static_cast<std::size_t>(t.end_count()));
  for (int end = 0; end < t.end_count(); ++end) {
    const int point = index.point_of_end(end);
    if (point < 0) {
      const Link& link = model.links[static_cast<std::size_t>(end / 2)];
      fail(link.origin, "links." + link.name,
           "no point named '" + (end % 2 == 0 ? link.from : link.to) + "'");
    }
    t.end_points[static_cast<std::size_t>(end)] = point;
  }

  // Every link end is in one group; the joints and supports, then one per point at most.
  t.groups.reserve(model.joints.size() + model.supports.size() + model.points.size());
  auto claim = [&](ConnectionGroup group, const Origin& origin, const auto& key_path) {
    const int index = static_cast<int>(t.groups.size());
    for (int end : group.ends) {
      int& owner = t.group_of_end[static_cast<std::size_t>(end)];
      if (owner >= 0)
        fail(origin, key_path(),
             "the end of link '" + model.links[static_cast<std::size_t>(end / 2)].name + "' at '" +
                 group.point + "' is already held by another joint or support");
      owner = index;
    }
    t.groups.push_back(std::move(group));
  };

  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    const EntityPath path{"joints", joint.name};
    claim({ConnectionGroup::Kind::joint, static_cast<int>(j), joint.at,
           named_ends(index, joint.at, joint.links, joint.origin, path)},
          joint.origin, [&] { return path.str(); });
  }
  for (std::size_t s = 0; s < model.supports.size(); ++s) {
    const Support& support = model.supports[s];
    const EntityPath path{"supports", support.name};
    claim({ConnectionGroup::Kind::support, static_cast<int>(s), support.at,
           named_ends(index, support.at, support.links, support.origin, path)},
          support.origin, [&] { return path.str(); });
  }

  // Link ends named nowhere: rigidly connected at their point, or free when alone there. The
  // points in the order of their first such end.
  std::vector<bool> point_done(model.points.size(), false);
  for (int first = 0; first < t.end_count(); ++first) {
    if (t.group_of_end[static_cast<std::size_t>(first)] >= 0) continue;
    const int point = t.end_points[static_cast<std::size_t>(first)];
    if (point_done[static_cast<std::size_t>(point)]) continue;
    point_done[static_cast<std::size_t>(point)] = true;
    const Point& p = model.points[static_cast<std::size_t>(point)];
    const auto at_point = index.ends_at(point);
    std::vector<int> ends;
    ends.reserve(at_point.size());
    bool some_held = false;
    for (const auto& e : at_point) {
      if (t.group_of_end[static_cast<std::size_t>(e.id())] >= 0)
        some_held = true;
      else
        ends.push_back(e.id());
    }
    if (some_held)
      fail(p.origin, "points." + p.name,
           "some link ends at this point are held by a joint or support and others (link '" +
               model.links[static_cast<std::size_t>(first / 2)].name +
               "') by nothing; name every end at the point in a joint or support");
    const auto kind = ends.size() == 1 ? ConnectionGroup::Kind::free_end
                                       : ConnectionGroup::Kind::rigid_connection;
    claim({kind, -1, p.name, std::move(ends)}, {}, [&] { return "points." + p.name; });
  }

  t.load_ends.reserve(model.loads.size());
  for (std::size_t i = 0; i < model.loads.size(); ++i) {
    const Load& load = model.loads[i];
    t.load_ends.push_back(end_of(index, load.at, load.link, load.origin,
                                 [&] { return "loads[" + std::to_string(i) + "]"; }));
  }
  const auto link_of = [&](const LinkLoad& load, const std::string& key) {
    const int link = index.link(load.link);
    if (link < 0) fail(load.origin, key, "no link named '" + load.link + "'");
    return link;
  };
  t.link_load_links.reserve(model.link_loads.size());
  for (std::size_t i = 0; i < model.link_loads.size(); ++i)
    t.link_load_links.push_back(
        link_of(model.link_loads[i], "loads[link " + std::to_string(i) + "]"));
  for (const LoadCase& c : model.load_cases) {
    std::vector<int>& ends = t.case_load_ends.emplace_back();
    for (std::size_t i = 0; i < c.loads.size(); ++i)
      ends.push_back(end_of(index, c.loads[i].at, c.loads[i].link, c.loads[i].origin, [&] {
        return "load_cases." + c.name + "[" + std::to_string(i) + "]";
      }));
    std::vector<int>& links = t.case_link_load_links.emplace_back();
    for (std::size_t i = 0; i < c.link_loads.size(); ++i)
      links.push_back(link_of(c.link_loads[i], "load_cases." + c.name));
  }
  t.effector_ends.reserve(model.end_effectors.size());
  for (const auto& effector : model.end_effectors)
    t.effector_ends.push_back(end_of(index, effector.at, effector.link, effector.origin,
                                     [&] { return "end_effectors." + effector.name; }));
  return t;
}

}  // namespace stiffmsa::detail
