#pragma once
// Which link end sits at a named point: the one rule that loads, end effectors, joints,
// supports and the topology all use.
#include <functional>
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
// which the names were added. Views the names, which must outlive it. An open-addressing table
// in one array (linear probing, at most half full): a model's index is built for every solve,
// and a node per name would be an allocation per name.
class NameTable {
 public:
  explicit NameTable(std::size_t names) : slots_(capacity_for(names)) {}
  // Adds `name` as the next position; returns the position of its first bearer.
  int add(std::string_view name) {
    if (2 * (used_ + 1) > slots_.size()) grow();
    Slot& slot = slots_[index_of(name, slots_)];
    if (slot.position < 0) {
      slot = {name, static_cast<int>(added_)};
      ++used_;
    }
    ++added_;
    return slot.position;
  }
  int find(std::string_view name) const {  // −1 when absent
    return slots_[index_of(name, slots_)].position;
  }

 private:
  struct Slot {
    std::string_view name;
    int position = -1;
  };
  static std::size_t capacity_for(std::size_t names) {
    std::size_t capacity = 8;
    while (capacity < 2 * names) capacity *= 2;
    return capacity;
  }
  // The slot that holds `name`, or the empty slot where it would go.
  static std::size_t index_of(std::string_view name, const std::vector<Slot>& slots) {
    const std::size_t mask = slots.size() - 1;
    for (std::size_t i = std::hash<std::string_view>{}(name)&mask;; i = (i + 1) & mask)
      if (slots[i].position < 0 || slots[i].name == name) return i;
  }
  void grow() {
    std::vector<Slot> larger(2 * slots_.size());
    for (const Slot& slot : slots_)
      if (slot.position >= 0) larger[index_of(slot.name, larger)] = slot;
    slots_ = std::move(larger);
  }
  std::vector<Slot> slots_;
  std::size_t used_ = 0;   // distinct names
  std::size_t added_ = 0;  // names added, repeats included
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
  std::optional<LinkEndRef> resolve(const std::string& point,
                                    const std::optional<std::string>& link_name,
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

// The defects of a model's values alone (Structure::find_value_defects), `index` being that of
// a model with the same names and connectivity.
std::vector<Diagnostic> find_value_defects(const Model& model, const ModelIndex& index);

}  // namespace stiffmsa::detail
