#pragma once
// Which link end sits at a named point: the one rule that loads, end effectors, joints,
// supports and the topology all use.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

struct LinkEndRef {
  int link = -1;  // index into Model::links
  LinkEnd end = LinkEnd::from;
  int id() const { return 2 * link + static_cast<int>(end); }
  bool operator==(const LinkEndRef&) const = default;
};

// Names to the position of the first entity that bears them, the position being the order in
// which the names were added. Views the names, which must outlive it.
class NameTable {
 public:
  explicit NameTable(std::size_t names) { positions_.reserve(names); }
  // Adds `name` as the next position; returns the position of its first bearer.
  int add(std::string_view name) {
    return positions_.try_emplace(name, static_cast<int>(added_++)).first->second;
  }
  int find(std::string_view name) const {  // −1 when absent
    const auto it = positions_.find(name);
    return it == positions_.end() ? -1 : it->second;
  }

 private:
  std::unordered_map<std::string_view, int> positions_;
  std::size_t added_ = 0;
};

// Name lookups of a model built once, for work that would otherwise scan the model per item
// (large models have 100 000 links). Refers to the model, which must outlive it.
class ModelIndex {
 public:
  explicit ModelIndex(const Model& model);
  const Point* point(std::string_view name) const;
  int point_position(std::string_view name) const { return points_.find(name); }  // −1 when absent
  // Whether two points or two links share a name (then a name finds the first of them).
  bool names_repeat() const { return names_repeat_; }
  int link(std::string_view name) const;  // −1 when absent
  // The position of the point at link end `end_id`, −1 where the link names no point.
  int point_of_end(int end_id) const { return point_of_end_[static_cast<std::size_t>(end_id)]; }
  // Every link end at `point`, in link order.
  std::span<const LinkEndRef> ends_at(std::string_view point) const;
  std::span<const LinkEndRef> ends_at(int point_position) const;
  // The link end meant by `{at: point, link: name}` (name optional). Sets `problem` to a
  // sentence and returns nullopt when there is no such end or the choice is ambiguous.
  std::optional<LinkEndRef> resolve(const std::string& point, const std::optional<std::string>& link_name,
                                    std::string& problem) const;

 private:
  const Model& model_;
  NameTable points_, links_;
  bool names_repeat_ = false;
  std::vector<int> point_of_end_;
  // The link ends grouped by point (the first of a repeated name), each group in link order;
  // group p is ends_[first_end_[p] .. first_end_[p + 1]).
  std::vector<int> first_end_;
  std::vector<LinkEndRef> ends_;
  // Ends at names that are no point: only an invalid model has them.
  std::unordered_map<std::string_view, std::vector<LinkEndRef>> ends_at_unknown_points_;
};

// stiffmsa::validate with the model's index already built (the analyses build the topology
// from the same index).
void validate(const Model& model, const ModelIndex& index);

}  // namespace stiffmsa::detail
