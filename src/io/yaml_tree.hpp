#pragma once
// The tree of a YAML (or JSON) text that the model loader reads: libfyaml parses, and this
// keeps only what the loader's checks and messages need (kinds, text, quoting, positions, every
// key as written), so the loader does not depend on the parser's own node types.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace stiffmsa::detail {

class YamlNode;

struct YamlEntry {
  const YamlNode* key;
  const YamlNode* value;
};

class YamlNode {
 public:
  enum class Kind : std::uint8_t { null, scalar, sequence, mapping };

  Kind kind() const { return kind_; }
  bool is_null() const { return kind_ == Kind::null; }
  bool is_scalar() const { return kind_ == Kind::scalar; }
  bool is_sequence() const { return kind_ == Kind::sequence; }
  bool is_mapping() const { return kind_ == Kind::mapping; }

  // The text of a scalar as the parser gives it (quotes and escapes resolved); empty for others.
  const std::string& text() const { return text_; }
  // Whether the file marks the scalar as text: written quoted or as a block scalar (| or >),
  // or tagged `!`. A quoted "2e11" is then not a number.
  bool quoted() const { return quoted_; }

  // Where the node starts, 1-based; 0 for a node that has no place in the text (an empty file).
  int line() const { return line_; }
  int column() const { return column_; }

  // The items of a sequence; empty for other kinds.
  std::span<const YamlNode* const> items() const { return items_; }
  // The entries of a mapping in the order of the text, each key as often as it is written:
  // the loader reports duplicates itself. Empty for other kinds.
  std::span<const YamlEntry> entries() const { return entries_; }
  // Items of a sequence or entries of a mapping; 0 for a scalar or null.
  std::size_t size() const { return is_mapping() ? entries_.size() : items_.size(); }

 private:
  friend class YamlTreeBuilder;
  Kind kind_ = Kind::null;
  bool quoted_ = false;
  // Values in the node with every alias in it spelt out (itself included), up to the budget.
  std::uint64_t expanded_ = 1;
  int line_ = 0;
  int column_ = 0;
  std::string text_;
  std::vector<const YamlNode*> items_;
  std::vector<YamlEntry> entries_;
};

// The first document of a text. Nodes that an alias repeats are one node, reached from each
// place (as anchors and aliases mean), so the tree is not copied out of proportion to the text.
class YamlTree {
 public:
  YamlTree() = default;
  // Nodes point at each other: a copy would point into the original.
  YamlTree(const YamlTree&) = delete;
  YamlTree& operator=(const YamlTree&) = delete;
  YamlTree(YamlTree&&) = default;
  YamlTree& operator=(YamlTree&&) = default;

  const YamlNode& root() const { return nodes_.front().front(); }

 private:
  friend class YamlTreeBuilder;
  // Nodes are made in blocks of this many, each reserved once, so that nodes stay where they
  // are (a deque's blocks hold four).
  static constexpr std::size_t kNodesPerBlock = 256;
  YamlNode& add_node() {
    if (nodes_.empty() || nodes_.back().size() == kNodesPerBlock) {
      nodes_.emplace_back().reserve(kNodesPerBlock);
    }
    return nodes_.back().emplace_back();
  }
  std::vector<std::vector<YamlNode>> nodes_;  // the root first
};

// Parses `text` (its name `file` goes into messages). Throws InputError for a syntax error
// ("YAML syntax error: ..." at the parser's line:column), and for mappings and lists nested
// deeper than `max_depth` levels, found while building (the tree is built without recursion,
// so hostile nesting costs no stack).
YamlTree parse_yaml(std::string_view text, const std::string& file, int max_depth);

// The message of nesting deeper than `max_depth` levels, with the depth the file reaches where
// it is known.
std::string nesting_too_deep_message(int max_depth, int deepest = 0);

}  // namespace stiffmsa::detail
