#include "model/link_ends.hpp"

namespace stiffmsa::detail {

int link_index(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.links.size(); ++i)
    if (model.links[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<LinkEndRef> ends_of_link_at(const Model& model, int link, const std::string& point) {
  std::vector<LinkEndRef> ends;
  const Link& l = model.links[static_cast<std::size_t>(link)];
  if (l.from == point) ends.push_back({link, LinkEnd::from});
  if (l.to == point) ends.push_back({link, LinkEnd::to});
  return ends;
}

std::vector<LinkEndRef> ends_at_point(const Model& model, const std::string& point) {
  std::vector<LinkEndRef> ends;
  for (int i = 0; i < static_cast<int>(model.links.size()); ++i)
    for (const auto& e : ends_of_link_at(model, i, point)) ends.push_back(e);
  return ends;
}

std::optional<LinkEndRef> resolve_link_end(const Model& model, const std::string& point,
                                           const std::optional<std::string>& link_name,
                                           std::string& problem) {
  if (link_name) {
    const int link = link_index(model, *link_name);
    if (link < 0) {
      problem = "no link named '" + *link_name + "'";
      return std::nullopt;
    }
    const auto ends = ends_of_link_at(model, link, point);
    if (ends.empty()) {
      problem = "link '" + *link_name + "' has no end at point '" + point + "'";
      return std::nullopt;
    }
    if (ends.size() > 1) {
      problem = "link '" + *link_name + "' has both ends at point '" + point +
                "'; the end cannot be chosen";
      return std::nullopt;
    }
    return ends.front();
  }
  const auto ends = ends_at_point(model, point);
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
