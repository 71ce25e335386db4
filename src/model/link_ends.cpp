#include "model/link_ends.hpp"

namespace stiffmsa::detail {

namespace {
LinkEndRef end_of_id(int id) { return {id / 2, id % 2 == 0 ? LinkEnd::from : LinkEnd::to}; }
}  // namespace

ModelIndex::ModelIndex(const Model& model)
    : model_(model), points_(model.points.size()), links_(model.links.size()) {
  for (std::size_t i = 0; i < model.points.size(); ++i)
    if (points_.add(model.points[i].name) != static_cast<int>(i)) names_repeat_ = true;
  point_of_end_.reserve(2 * model.links.size());
  first_end_.assign(model.points.size() + 1, 0);
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const Link& l = model.links[i];
    if (links_.add(l.name) != static_cast<int>(i)) names_repeat_ = true;
    for (const std::string* name : {&l.from, &l.to}) {
      const int p = points_.find(*name);
      point_of_end_.push_back(p);
      if (p >= 0)
        ++first_end_[static_cast<std::size_t>(p)];
      else
        ends_at_unknown_points_[*name].push_back(
            end_of_id(static_cast<int>(point_of_end_.size()) - 1));
    }
  }
  // The counts summed up mark where each group ends; placing the ends last to first moves
  // each mark down to where its group starts, and keeps every group in link order.
  for (std::size_t p = 1; p < first_end_.size(); ++p) first_end_[p] += first_end_[p - 1];
  ends_.resize(static_cast<std::size_t>(first_end_.back()));
  for (auto id = static_cast<int>(point_of_end_.size()); id-- > 0;)
    if (const int p = point_of_end_[static_cast<std::size_t>(id)]; p >= 0)
      ends_[static_cast<std::size_t>(--first_end_[static_cast<std::size_t>(p)])] = end_of_id(id);
}

const Point* ModelIndex::point(std::string_view name) const {
  const int p = points_.find(name);
  return p < 0 ? nullptr : &model_.points[static_cast<std::size_t>(p)];
}

int ModelIndex::link(std::string_view name) const { return links_.find(name); }

std::span<const LinkEndRef> ModelIndex::ends_at(int point_position) const {
  const auto p = static_cast<std::size_t>(point_position);
  return std::span<const LinkEndRef>(ends_).subspan(
      static_cast<std::size_t>(first_end_[p]),
      static_cast<std::size_t>(first_end_[p + 1] - first_end_[p]));
}

std::span<const LinkEndRef> ModelIndex::ends_at(std::string_view point) const {
  if (const int p = points_.find(point); p >= 0) return ends_at(p);
  const auto it = ends_at_unknown_points_.find(point);
  if (it == ends_at_unknown_points_.end()) return {};
  return it->second;
}

std::optional<LinkEndRef> ModelIndex::resolve(const std::string& point,
                                              const std::optional<std::string>& link_name,
                                              std::string& problem) const {
  if (link_name) {
    const int index = link(*link_name);
    if (index < 0) {
      problem = "no link named '" + *link_name + "'";
      return std::nullopt;
    }
    const Link& l = model_.links[static_cast<std::size_t>(index)];
    const bool from_here = l.from == point, to_here = l.to == point;
    if (!from_here && !to_here) {
      problem = "link '" + *link_name + "' has no end at point '" + point + "'";
      return std::nullopt;
    }
    if (from_here && to_here) {
      problem = "link '" + *link_name + "' has both ends at point '" + point +
                "'; the end cannot be chosen";
      return std::nullopt;
    }
    return LinkEndRef{index, from_here ? LinkEnd::from : LinkEnd::to};
  }
  const auto ends = ends_at(point);
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
