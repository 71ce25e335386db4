#include "model/link_ends.hpp"

namespace stiffmsa::detail {

namespace {
// The ends of link number `link` at `point`: none, one, or both (a link from a point to itself).
std::vector<LinkEndRef> ends_of_link_at(const Model& model, int link, const std::string& point) {
  std::vector<LinkEndRef> ends;
  const Link& l = model.links[static_cast<std::size_t>(link)];
  if (l.from == point) ends.push_back({link, LinkEnd::from});
  if (l.to == point) ends.push_back({link, LinkEnd::to});
  return ends;
}
}  // namespace

ModelIndex::ModelIndex(const Model& model) : model_(model) {
  points_.reserve(model.points.size());
  for (std::size_t i = 0; i < model.points.size(); ++i) points_.try_emplace(model.points[i].name, static_cast<int>(i));
  links_.reserve(model.links.size());
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const Link& l = model.links[i];
    links_.try_emplace(l.name, static_cast<int>(i));
    ends_[l.from].push_back({static_cast<int>(i), LinkEnd::from});
    ends_[l.to].push_back({static_cast<int>(i), LinkEnd::to});
  }
}

const Point* ModelIndex::point(const std::string& name) const {
  const auto it = points_.find(name);
  return it == points_.end() ? nullptr : &model_.points[static_cast<std::size_t>(it->second)];
}

int ModelIndex::link(const std::string& name) const {
  const auto it = links_.find(name);
  return it == links_.end() ? -1 : it->second;
}

const std::vector<LinkEndRef>& ModelIndex::ends_at(const std::string& point) const {
  static const std::vector<LinkEndRef> none;
  const auto it = ends_.find(point);
  return it == ends_.end() ? none : it->second;
}

std::optional<LinkEndRef> ModelIndex::resolve(const std::string& point, const std::optional<std::string>& link_name,
                                              std::string& problem) const {
  if (link_name) {
    const int index = link(*link_name);
    if (index < 0) {
      problem = "no link named '" + *link_name + "'";
      return std::nullopt;
    }
    const auto ends = ends_of_link_at(model_, index, point);
    if (ends.empty()) {
      problem = "link '" + *link_name + "' has no end at point '" + point + "'";
      return std::nullopt;
    }
    if (ends.size() > 1) {
      problem = "link '" + *link_name + "' has both ends at point '" + point + "'; the end cannot be chosen";
      return std::nullopt;
    }
    return ends.front();
  }
  const auto& ends = ends_at(point);
  if (ends.empty()) {
    problem = "no link end is at point '" + point + "'";
    return std::nullopt;
  }
  if (ends.size() > 1) {
    problem = "several link ends are at point '" + point + "'; name one with `link:`";
    return std::nullopt;
  }
  return ends.front();
}

}  // namespace stiffmsa::detail
