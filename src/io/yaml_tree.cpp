// The loader's YAML tree built from libfyaml's events: one pass, no recursion, and no document
// of libfyaml's own kept alongside it.
#include "io/yaml_tree.hpp"

#include <algorithm>

#include <libfyaml.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <optional>
#include <unordered_map>
#include <utility>

#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

std::string nesting_too_deep_message(int max_depth, int deepest) {
  return "mappings and lists nest deeper here than the limit of " + std::to_string(max_depth) +
         " levels" + (deepest > 0 ? " (the file reaches " + std::to_string(deepest) + ")" : "") +
         "; if the model is meant to nest this deep, raise the limit "
         "(LoadLimits::max_nesting_depth)";
}

namespace {

// The library never prints: libfyaml's messages are collected and read from the diag instead.
void discard_output(fy_diag*, void*, const char*, size_t) {}

struct DiagDeleter {
  void operator()(fy_diag* diag) const { fy_diag_destroy(diag); }
};
struct ParserDeleter {
  void operator()(fy_parser* parser) const { fy_parser_destroy(parser); }
};

std::string_view text_of(fy_token* token) {
  if (token == nullptr) return {};
  std::size_t length = 0;
  const char* text = fy_token_get_text(token, &length);
  return text == nullptr ? std::string_view{} : std::string_view(text, length);
}

// The null spellings of YAML 1.2's core schema, which model files have relied on.
bool spells_null(std::string_view text) {
  return text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL";
}

}  // namespace

class YamlTreeBuilder {
 public:
  YamlTreeBuilder(std::string_view text, const std::string& file, int max_depth)
      : text_(text), file_(file), max_depth_(max_depth) {}

  YamlTree build() {
    fy_diag_cfg diag_cfg;
    fy_diag_cfg_default(&diag_cfg);
    diag_cfg.fp = nullptr;
    diag_cfg.output_fn = discard_output;
    diag_cfg.colorize = false;
    // The lines of source that libfyaml would format around an error are not used; formatting
    // them is where its fuzzers have found out-of-bounds reads (libfyaml issues #189, #223).
    diag_cfg.show_source = false;
    const std::unique_ptr<fy_diag, DiagDeleter> diag(fy_diag_create(&diag_cfg));
    if (!diag) throw std::bad_alloc();
    fy_diag_set_collect_errors(diag.get(), true);

    // JSON is read as the YAML it is. Flow collections may continue on lines indented no
    // deeper than their key (`K: [[1, 0],` over `[0, 1]]`), as model files have been written
    // by earlier versions of stiffmsa. The depth limit of libfyaml is its guard for recursive
    // algorithms; events are produced without recursion, and depth is limited here.
    fy_parse_cfg parse_cfg{};
    parse_cfg.flags = static_cast<fy_parse_cfg_flags>(
        FYPCF_QUIET | FYPCF_JSON_NONE | FYPCF_SLOPPY_FLOW_INDENTATION | FYPCF_DISABLE_DEPTH_LIMIT);
    parse_cfg.diag = diag.get();
    const std::unique_ptr<fy_parser, ParserDeleter> parser(fy_parser_create(&parse_cfg));
    // libfyaml refuses a null pointer even for no text.
    const char* text = text_.empty() ? "" : text_.data();
    if (!parser || fy_parser_set_string(parser.get(), text, text_.size()) != 0)
      throw std::bad_alloc();

    const auto free_event = [&](fy_event* event) { fy_parser_event_free(parser.get(), event); };
    bool document_ended = false;
    while (!document_ended) {
      const std::unique_ptr<fy_event, decltype(free_event)> event(fy_parser_parse(parser.get()),
                                                                  free_event);
      if (!event) {
        if (fy_parser_get_stream_error(parser.get())) throw_syntax_error(diag.get());
        break;  // the end of a stream without documents
      }
      document_ended = take(event.get());
    }
    if (tree_.nodes_.empty()) tree_.add_node();  // no document: a null root
    return std::move(tree_);
  }

 private:
  // Where a node is, 1-based (0 for no place); made into a SourceLocation, which holds the
  // file's name, only for a message.
  struct Place {
    int line = 0;
    int column = 0;
  };

  struct Open {
    YamlNode* node;
    const YamlNode* pending_key = nullptr;  // a mapping's key whose value comes next
    std::optional<Place> bracket;           // where a flow collection's `[` or `{` is
    // Where its items (a sequence's) or entries (a mapping's) start in items_ or entries_ below:
    // gathered there while it is open, and moved into the node, at their exact size, at its end.
    std::size_t first_child = 0;
    // A single `key: value` pair in a flow list has no `{`: it starts where its key does.
    bool starts_at_first_key = false;
  };

  // Returns whether the first document has ended: a model file is one document, and what
  // follows it has never been read.
  bool take(fy_event* event) {
    place_empty_nodes(event);
    switch (event->type) {
      case FYET_DOCUMENT_END: return true;
      case FYET_SCALAR: add(scalar(event), event->scalar.anchor); return false;
      case FYET_ALIAS: {
        const YamlNode* repeated = alias(event);
        // Aliases that repeat aliases grow the values a reader walks exponentially in the
        // length of the text ("billion laughs"): spelt out, the document must stay within a
        // budget proportional to its text.
        expanded_ = std::min(kUnbounded, expanded_ + repeated->expanded_);
        if (expanded_ > expansion_budget())
          throw InputError(
              located(node_start(event->alias.anchor, nullptr, nullptr)), "",
              "aliases repeat so much that the document, spelt out, would hold more than " +
                  std::to_string(expansion_budget()) +
                  " values; write the repeated parts out, or repeat less");
        add_existing(repeated);
        return false;
      }
      case FYET_SEQUENCE_START:
      case FYET_MAPPING_START: open(event); return false;
      case FYET_SEQUENCE_END:
      case FYET_MAPPING_END: {
        if (open_.empty()) return false;  // libfyaml pairs every end with its start
        YamlNode* done = open_.back().node;
        const std::size_t first = open_.back().first_child;
        if (done->is_sequence()) {
          done->items_.assign(items_.begin() + static_cast<std::ptrdiff_t>(first), items_.end());
          items_.resize(first);
        } else {
          done->entries_.assign(entries_.begin() + static_cast<std::ptrdiff_t>(first),
                                entries_.end());
          entries_.resize(first);
        }
        open_.pop_back();
        add_existing(done);
        return false;
      }
      default: return false;
    }
  }

  static Place place_of(const fy_mark* mark) {
    if (mark == nullptr) return {};
    return {mark->line + 1, mark->column + 1};
  }
  SourceLocation located(Place place) const { return {file_, place.line, place.column}; }

  // The character that opens a token before where libfyaml marks it: a quote, `&` or `*`.
  static char indicator_of(fy_token* token) {
    switch (fy_token_get_type(token)) {
      case FYTT_SCALAR:
        return fy_token_scalar_style(token) == FYSS_SINGLE_QUOTED   ? '\''
               : fy_token_scalar_style(token) == FYSS_DOUBLE_QUOTED ? '"'
                                                                    : '\0';
      case FYTT_ANCHOR: return '&';
      case FYTT_ALIAS: return '*';
      default: return '\0';
    }
  }

  // libfyaml marks a quoted scalar after its opening quote; messages point at the quote, where
  // the value begins for the reader.
  std::optional<fy_mark> start_of(fy_token* token) const {
    const fy_mark* mark = token != nullptr ? fy_token_start_mark(token) : nullptr;
    if (mark == nullptr) return std::nullopt;
    fy_mark start = *mark;
    if (start.input_pos == 0 || start.input_pos > text_.size()) return start;
    if (fy_token_get_type(token) == FYTT_SCALAR && (fy_token_scalar_style(token) == FYSS_LITERAL ||
                                                    fy_token_scalar_style(token) == FYSS_FOLDED))
      return block_scalar_header(start).value_or(start);
    const char indicator = indicator_of(token);
    const bool indicator_before = indicator != '\0' && text_[start.input_pos - 1] == indicator;
    if (indicator_before && start.column > 0) {
      --start.input_pos;
      --start.column;
    }
    return start;
  }

  // libfyaml marks a block scalar (| or >) at its first line of text; it starts at the
  // indicator: the last `|` or `>` before any comment on the nearest line that is not blank,
  // the line of the mark itself included (a block scalar without text is marked there).
  std::optional<fy_mark> block_scalar_header(const fy_mark& content) const {
    constexpr auto npos = std::string_view::npos;
    std::size_t end = content.input_pos;  // the header is looked for before this
    for (int line = content.line; line >= 0; --line) {
      const std::size_t newline = end == 0 ? npos : text_.rfind('\n', end - 1);
      const std::size_t begin = newline == npos ? 0 : newline + 1;
      const std::string_view header = text_.substr(begin, end - begin);
      if (header.find_first_not_of(" \t\r") != npos) {
        std::size_t code_end = header.size();
        for (std::size_t i = 0; i < header.size(); ++i)
          if (header[i] == '#' && (i == 0 || header[i - 1] == ' ' || header[i - 1] == '\t')) {
            code_end = i;
            break;
          }
        const std::size_t indicator = header.substr(0, code_end).find_last_of("|>");
        if (indicator == npos) return std::nullopt;
        return fy_mark{begin + indicator, line, static_cast<int>(indicator)};
      }
      if (newline == npos) break;
      end = newline;
    }
    return std::nullopt;
  }

  // A node starts with its properties: `&anchor` and `!tag` come before its value.
  Place node_start(fy_token* value, fy_token* anchor, fy_token* tag) const {
    std::optional<fy_mark> first;
    for (fy_token* token : {value, anchor, tag})
      if (const auto start = start_of(token);
          start && (!first || start->input_pos < first->input_pos))
        first = start;
    return first ? place_of(&*first) : Place{};
  }

  YamlNode& new_node(YamlNode::Kind kind, Place at) {
    ++expanded_;
    YamlNode& node = tree_.add_node();
    node.kind_ = kind;
    node.line_ = at.line;
    node.column_ = at.column;
    if (at.line == 0) unplaced_.push_back(&node);
    return node;
  }

  // An empty value (`key:` or `-` with nothing after it) or key (`: value`) has no text of its
  // own. As messages have always placed it, it goes at what follows it: the `-`, `?` or `:` just
  // before the next node, or else that node.
  void place_empty_nodes(fy_event* event) {
    if (unplaced_.empty()) return;
    std::optional<fy_mark> next = start_of(fy_event_get_token(event));
    if (!next) return;
    std::size_t before = next->input_pos;
    while (before > 0 && (text_[before - 1] == ' ' || text_[before - 1] == '\t')) --before;
    const std::size_t moved = next->input_pos - before;
    if (before > 0 && moved > 0 && static_cast<int>(moved) < next->column &&
        (text_[before - 1] == '-' || text_[before - 1] == '?' || text_[before - 1] == ':')) {
      next->input_pos = before - 1;
      next->column -= static_cast<int>(moved) + 1;
    }
    for (YamlNode* node : unplaced_) {
      node->line_ = next->line + 1;
      node->column_ = next->column + 1;
    }
    unplaced_.clear();
  }

  void remember_anchor(fy_token* anchor, const YamlNode& node) {
    if (anchor != nullptr) anchors_[std::string(text_of(anchor))] = &node;
  }

  YamlNode& scalar(fy_event* event) {
    fy_token* value = event->scalar.value;
    fy_token* tag = event->scalar.tag;
    const bool plain = fy_token_scalar_style(value) == FYSS_PLAIN;
    const std::string_view text = text_of(value);
    // An explicit tag decides, else quoting or block style makes text ("!"): the rule the
    // loader's "a quoted number is text" rests on.
    const char* tag_text = tag != nullptr ? fy_token_get_text0(tag) : nullptr;
    const bool quoted = tag_text != nullptr ? std::string_view(tag_text) == "!" : !plain;
    const bool null = plain && tag == nullptr && spells_null(text);
    // A plain scalar without properties, most of a model file, starts where libfyaml marks it.
    const bool bare = plain && tag == nullptr && event->scalar.anchor == nullptr;
    YamlNode& node = new_node(
        null ? YamlNode::Kind::null : YamlNode::Kind::scalar,
        bare ? place_of(fy_token_start_mark(value)) : node_start(value, event->scalar.anchor, tag));
    if (!null) node.text_ = text;
    node.quoted_ = quoted;
    return node;
  }

  const YamlNode* alias(fy_event* event) {
    const std::string name(text_of(event->alias.anchor));
    const auto found = anchors_.find(name);
    if (found == anchors_.end())
      throw InputError(located(node_start(event->alias.anchor, nullptr, nullptr)), "",
                       "YAML syntax error: the alias '*" + name +
                           "' names no anchor given before it (as '&" + name + "')");
    return found->second;
  }

  void open(fy_event* event) {
    const bool is_mapping = event->type == FYET_MAPPING_START;
    fy_token* start =
        is_mapping ? event->mapping_start.mapping_start : event->sequence_start.sequence_start;
    fy_token* anchor = is_mapping ? event->mapping_start.anchor : event->sequence_start.anchor;
    fy_token* tag = is_mapping ? event->mapping_start.tag : event->sequence_start.tag;
    // A block collection has no start token: it starts where its first key or item does.
    Place at = node_start(start, anchor, tag);
    if (start == nullptr && anchor == nullptr && tag == nullptr)
      at = place_of(fy_event_start_mark(event));
    YamlNode& node = new_node(is_mapping ? YamlNode::Kind::mapping : YamlNode::Kind::sequence, at);
    if (static_cast<int>(open_.size()) >= max_depth_)
      throw InputError(located(at), "", nesting_too_deep_message(max_depth_));
    remember_anchor(anchor, node);
    Open opened{&node, nullptr, std::nullopt, is_mapping ? entries_.size() : items_.size(), false};
    // A `[` or `{` told by its token's type: libfyaml formats a token's text anew for each
    // call, 2 000 instructions for one character.
    const fy_token_type start_type = start != nullptr ? fy_token_get_type(start) : FYTT_NONE;
    const bool bracket =
        start_type == FYTT_FLOW_SEQUENCE_START || start_type == FYTT_FLOW_MAPPING_START;
    if (bracket) opened.bracket = place_of(fy_token_start_mark(start));
    // libfyaml marks such a pair at its `:`, or at its `?` where it has one, which is its start.
    opened.starts_at_first_key = is_mapping && !bracket && anchor == nullptr && tag == nullptr &&
                                 fy_event_get_node_style(event) == FYNS_FLOW &&
                                 text_of(start).empty();
    open_.push_back(opened);
  }

  void add(YamlNode& node, fy_token* anchor) {
    remember_anchor(anchor, node);
    add_existing(&node);
  }

  void add_existing(const YamlNode* node) {
    if (open_.empty()) return;  // the root, which is nodes_.front()
    Open& parent = open_.back();
    parent.node->expanded_ = std::min(kUnbounded, parent.node->expanded_ + node->expanded_);
    if (parent.starts_at_first_key) {
      // An empty key (`[: v]`) has no place yet: the pair stays at its `:`.
      if (node->line_ > 0) {
        parent.node->line_ = node->line_;
        parent.node->column_ = node->column_;
      }
      parent.starts_at_first_key = false;
    }
    if (parent.node->is_sequence()) {
      items_.push_back(node);
    } else if (parent.pending_key == nullptr) {
      parent.pending_key = node;
    } else {
      entries_.push_back({parent.pending_key, node});
      parent.pending_key = nullptr;
    }
  }

  // libfyaml's first error, at its position; within a flow collection the message also says
  // where that opens, which is where a bracket that is never closed is to be found.
  [[noreturn]] void throw_syntax_error(fy_diag* diag) const {
    SourceLocation at{file_, 0, 0};
    std::string message = "the text is not valid YAML";
    void* iterator = nullptr;
    while (const fy_diag_error* error = fy_diag_errors_iterate(diag, &iterator)) {
      if (error->type < FYET_ERROR) continue;
      if (error->msg != nullptr) message = error->msg;
      const std::optional<fy_mark> mark = start_of(error->fyt);
      at = mark ? located(place_of(&*mark)) : SourceLocation{file_, error->line, error->column};
      break;
    }
    for (auto open = open_.rbegin(); open != open_.rend(); ++open) {
      if (!open->bracket) continue;
      message += std::string(" (in the ") + (open->node->is_mapping() ? "mapping" : "list") +
                 " that '" + (open->node->is_mapping() ? "{" : "[") + "' opens at line " +
                 std::to_string(open->bracket->line) + ", column " +
                 std::to_string(open->bracket->column) + ")";
      break;
    }
    throw InputError(at, "", "YAML syntax error: " + message);
  }

  std::string_view text_;
  const std::string& file_;
  int max_depth_;
  YamlTree tree_;
  std::vector<Open> open_;              // the collections being read, the innermost last
  std::vector<YamlNode*> unplaced_;     // empty values that wait for what follows them
  std::vector<const YamlNode*> items_;  // of the open sequences, the innermost's last
  std::vector<YamlEntry> entries_;      // of the open mappings, the innermost's last
  std::unordered_map<std::string, const YamlNode*> anchors_;
  // Values of the document spelt out so far: nodes made, plus what every alias repeats.
  static constexpr std::uint64_t kUnbounded = std::uint64_t{1} << 62;
  std::uint64_t expanded_ = 0;
  std::uint64_t expansion_budget() const {
    return 4 * static_cast<std::uint64_t>(text_.size()) + 1'000'000;
  }
};

namespace {

// The length of the UTF-8 sequence that starts `text` (1 to 4), or 0 where it is malformed:
// a stray continuation byte, an overlong form, a surrogate or a code point above U+10FFFF.
std::size_t utf8_sequence_length(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (text.size() < length || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i)
    if (byte(i) < 0x80 || byte(i) > 0xBF) return 0;
  return length;
}

// Where the byte at `at` is, 1-based, its column counted in characters: the text before it is
// valid UTF-8, so each byte that is not a continuation byte (10xxxxxx) starts one character.
std::pair<int, int> line_and_column(std::string_view text, std::size_t at) {
  const std::string_view before = text.substr(0, at);
  const std::size_t line_start = before.rfind('\n') + 1;  // npos + 1 is 0
  const auto is_character_start = [](char c) {
    return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  };
  const auto line = 1 + std::count(before.begin(), before.end(), '\n');
  const auto column = 1 + std::count_if(before.begin() + static_cast<std::ptrdiff_t>(line_start),
                                        before.end(), is_character_start);
  return {static_cast<int>(line), static_cast<int>(column)};
}

// Model files are UTF-8. Checked before parsing: libfyaml (0.7.12) loops without end on some
// malformed bytes (one in a directive line, found by the fuzz target), and reads others at the
// start of a plain value as an empty value.
void require_utf8(std::string_view text, const std::string& file) {
  constexpr std::uint64_t kHighBits = 0x8080808080808080u;
  for (std::size_t at = 0; at < text.size();) {
    // ASCII, the bulk of a model file, eight bytes at a time.
    std::uint64_t eight = 0;
    if (text.size() - at >= sizeof eight) {
      std::memcpy(&eight, text.data() + at, sizeof eight);
      if ((eight & kHighBits) == 0) {
        at += sizeof eight;
        continue;
      }
    }
    const std::size_t length = utf8_sequence_length(text.substr(at));
    if (length == 0) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned char>(text[at]));
      const auto [line, column] = line_and_column(text, at);
      throw InputError(SourceLocation{file, line, column}, "",
                       std::string("the file is not UTF-8 text: the byte ") + hex +
                           " here begins no UTF-8 character; save the model as UTF-8");
    }
    at += length;
  }
}

}  // namespace

YamlTree parse_yaml(std::string_view text, const std::string& file, int max_depth) {
  require_utf8(text, file);
  return YamlTreeBuilder(text, file, max_depth).build();
}

}  // namespace stiffmsa::detail
