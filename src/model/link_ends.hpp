#pragma once
// Which link end sits at a named point: the one rule that loads, end effectors, joints,
// supports and the topology all use.
#include <optional>
#include <string>
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

// Name lookups of a model built once, for work that would otherwise scan the model per item
// (large models have 100 000 links). Refers to the model, which must outlive it.
class ModelIndex {
 public:
  explicit ModelIndex(const Model& model);
  const Point* point(const std::string& name) const;
  int link(const std::string& name) const;  // −1 when absent
  // Every link end at `point`, in link order.
  const std::vector<LinkEndRef>& ends_at(const std::string& point) const;
  // The link end meant by `{at: point, link: name}` (name optional). Sets `problem` to a
  // sentence and returns nullopt when there is no such end or the choice is ambiguous.
  std::optional<LinkEndRef> resolve(const std::string& point, const std::optional<std::string>& link_name,
                                    std::string& problem) const;

 private:
  const Model& model_;
  std::unordered_map<std::string, int> points_, links_;
  std::unordered_map<std::string, std::vector<LinkEndRef>> ends_;
};

}  // namespace stiffmsa::detail
