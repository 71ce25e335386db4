// The YAML tree the model loader reads (io/yaml_tree): what it keeps of a text for the loader's
// checks and messages — quoting, 1-based positions, every key as written — and that hostile
// nesting is refused without using up the stack.
#include <gtest/gtest.h>

#include <string>

#include "io/yaml_tree.hpp"
#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {
namespace {

constexpr int kDepth = 64;

const YamlNode& value_of(const YamlNode& mapping, const std::string& key) {
  for (const auto& [k, v] : mapping.entries())
    if (k->text() == key) return *v;
  ADD_FAILURE() << "no key '" << key << "'";
  return mapping;
}

// The one diagnostic of a refused text.
Diagnostic refusal_of(const std::string& text, int max_depth = kDepth) {
  try {
    parse_yaml(text, "t.yaml", max_depth);
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostics().size(), 1u);
    return e.diagnostics().front();
  }
  ADD_FAILURE() << "the text was accepted:\n" << text;
  return {};
}

TEST(YamlTree, QuotedBlockAndBangTaggedScalarsAreText) {
  const YamlTree tree = parse_yaml(
      "plain: 2e11\ndouble: \"2e11\"\nsingle: '2e11'\nliteral: |\n  2e11\nfolded: >\n  2e11\n"
      "bang: ! 2e11\nstr: !!str 2e11\n",
      "t.yaml", kDepth);
  const YamlNode& root = tree.root();
  for (const char* key : {"plain", "double", "single", "literal", "folded", "bang", "str"})
    EXPECT_TRUE(value_of(root, key).is_scalar()) << key;
  EXPECT_FALSE(value_of(root, "plain").quoted());
  EXPECT_TRUE(value_of(root, "double").quoted());
  EXPECT_TRUE(value_of(root, "single").quoted());
  EXPECT_TRUE(value_of(root, "literal").quoted());
  EXPECT_TRUE(value_of(root, "folded").quoted());
  EXPECT_TRUE(value_of(root, "bang").quoted());
  // An explicit tag other than `!` says what the value is; quoting does not decide.
  EXPECT_FALSE(value_of(root, "str").quoted());
  EXPECT_EQ(value_of(root, "double").text(), "2e11");
  EXPECT_EQ(value_of(root, "literal").text(), "2e11\n");
  EXPECT_EQ(value_of(root, "str").text(), "2e11");
}

TEST(YamlTree, PlainNullSpellingsAndEmptyValuesAreNull) {
  const YamlTree tree =
      parse_yaml("a: ~\nb: null\nc: Null\nd: NULL\ne:\nf: \"null\"\ng: nil\n", "t.yaml", kDepth);
  const YamlNode& root = tree.root();
  for (const char* key : {"a", "b", "c", "d", "e"})
    EXPECT_TRUE(value_of(root, key).is_null()) << key;
  EXPECT_TRUE(value_of(root, "f").is_scalar());
  EXPECT_EQ(value_of(root, "f").text(), "null");
  EXPECT_TRUE(value_of(root, "g").is_scalar());
}

TEST(YamlTree, EmptyTextIsANullRoot) {
  EXPECT_TRUE(parse_yaml("", "t.yaml", kDepth).root().is_null());
  EXPECT_TRUE(parse_yaml("# a comment only\n", "t.yaml", kDepth).root().is_null());
}

TEST(YamlTree, PositionsAreOneBasedWhereTheNodeBegins) {
  const YamlTree tree = parse_yaml(
      "format: stiffmsa/1\n"
      "points:\n"
      "  O: [0, \"1\", 2]\n"
      "  A: &a {x: 'q'}\n"
      "text: |\n"
      "  lines\n",
      "t.yaml", kDepth);
  const YamlNode& root = tree.root();
  EXPECT_EQ(root.line(), 1);
  EXPECT_EQ(root.column(), 1);
  const YamlNode& points = value_of(root, "points");
  EXPECT_EQ(points.line(), 3);  // a block mapping starts at its first key
  EXPECT_EQ(points.column(), 3);
  const YamlNode& o = value_of(points, "O");
  EXPECT_EQ(o.column(), 6);  // its `[`
  ASSERT_EQ(o.size(), 3u);
  EXPECT_EQ(o.items()[1]->column(), 10);  // a quoted scalar starts at its quote
  const YamlNode& a = value_of(points, "A");
  EXPECT_EQ(a.line(), 4);
  EXPECT_EQ(a.column(), 6);  // an anchored node starts at its `&`
  EXPECT_EQ(value_of(a, "x").column(), 13);
  const YamlNode& text = value_of(root, "text");
  EXPECT_EQ(text.line(), 5);  // a block scalar starts at its `|`
  EXPECT_EQ(text.column(), 7);
  const auto& keys = points.entries();
  EXPECT_EQ(keys[1].key->line(), 4);
  EXPECT_EQ(keys[1].key->column(), 3);
}

TEST(YamlTree, AnEmptyListItemIsPlacedAtTheItemAfterIt) {
  const YamlTree tree = parse_yaml("l:\n  - 1\n  -\n  - 2\n", "t.yaml", kDepth);
  const YamlNode& list = value_of(tree.root(), "l");
  ASSERT_EQ(list.size(), 3u);
  EXPECT_TRUE(list.items()[1]->is_null());
  EXPECT_EQ(list.items()[1]->line(), 4);
  EXPECT_EQ(list.items()[1]->column(), 3);
}

TEST(YamlTree, DuplicateKeysAreKeptInTheirOrder) {
  const YamlTree tree = parse_yaml("a: 1\nb: 2\na: 3\n", "t.yaml", kDepth);
  const auto& entries = tree.root().entries();
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].key->text(), "a");
  EXPECT_EQ(entries[2].key->text(), "a");
  EXPECT_EQ(entries[2].key->line(), 3);
  EXPECT_EQ(entries[2].value->text(), "3");
}

TEST(YamlTree, AnAliasIsTheAnchoredNode) {
  const YamlTree tree = parse_yaml("a: &steel {E: 1}\nb: *steel\n", "t.yaml", kDepth);
  const auto& entries = tree.root().entries();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].value, entries[1].value);
  // Merge keys are not expanded: `<<` is a key like any other, for the loader to refuse.
  const YamlTree merged = parse_yaml("a: &x {E: 1}\nb: {<<: *x}\n", "t.yaml", kDepth);
  EXPECT_EQ(value_of(merged.root(), "b").entries()[0].key->text(), "<<");
}

TEST(YamlTree, AnAliasOfNoAnchorIsASyntaxError) {
  const Diagnostic d = refusal_of("a: 1\nb: *steel\n");
  EXPECT_EQ(d.location.file, "t.yaml");
  EXPECT_EQ(d.location.line, 2);
  EXPECT_EQ(d.location.column, 4);
  EXPECT_EQ(d.message.rfind("YAML syntax error: ", 0), 0u) << d.message;
  EXPECT_NE(d.message.find("'*steel'"), std::string::npos) << d.message;
}

TEST(YamlTree, AliasesThatMultiplyBeyondTheBudgetAreRefusedAtTheAlias) {
  // Nine levels of ten aliases each: 10^9 values spelt out, from 400 bytes of text.
  std::string text = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level <= 9; ++level) {
    const std::string previous = "*l" + std::to_string(level - 1);
    text += "l" + std::to_string(level) + ": &l" + std::to_string(level) + " [" + previous;
    for (int k = 1; k < 10; ++k) text += ", " + previous;
    text += "]\n";
  }
  const Diagnostic d = refusal_of(text);
  EXPECT_NE(d.message.find("aliases repeat so much"), std::string::npos) << d.message;
  // The budget, 1 000 000 + 4 per byte of text, is passed by the ninth alias on line 6 (each
  // *l4 spells out 111 111 values).
  EXPECT_EQ(d.location.line, 6);
  // Repeating a part a few times is still read.
  const YamlTree tree = parse_yaml("a: &a [1, 2, 3]\nb: [*a, *a, *a]\n", "t.yaml", kDepth);
  EXPECT_EQ(value_of(tree.root(), "b").size(), 3u);
}

TEST(YamlTree, BytesThatAreNoUtf8AreRefusedWhereTheyStand) {
  // Found by the fuzz target: libfyaml loops without end on this directive line.
  const Diagnostic directive = refusal_of(std::string("# I1\n%lid\xff\0oints: {}\n", 21));
  EXPECT_EQ(directive.location.line, 2);
  EXPECT_EQ(directive.location.column, 5);
  EXPECT_NE(directive.message.find("not UTF-8"), std::string::npos) << directive.message;
  EXPECT_NE(directive.message.find("0xff"), std::string::npos) << directive.message;
  // Overlong forms, surrogates, truncated sequences.
  for (const char* bad :
       {"a: \xc0\xaf\n", "a: \xed\xa0\x80\n", "a: \xe2\x82\n", "a: \xf5\x80\x80\x80\n"})
    EXPECT_EQ(refusal_of(bad).location.column, 4) << bad;
  // Text in other scripts is read.
  const YamlTree tree = parse_yaml(
      "name: \"Schulter-Gelenk \xc3\xa4 \xe2\x88\x86 \xf0\x9f\xa4\x96\"\n", "t.yaml", kDepth);
  EXPECT_EQ(value_of(tree.root(), "name").text(),
            "Schulter-Gelenk \xc3\xa4 \xe2\x88\x86 \xf0\x9f\xa4\x96");
}

TEST(YamlTree, ASyntaxErrorInAFlowCollectionSaysWhereItOpens) {
  const Diagnostic d = refusal_of("a: [1, 2\nb: 3\n");
  EXPECT_EQ(d.location.line, 3);
  EXPECT_EQ(d.message.rfind("YAML syntax error: ", 0), 0u) << d.message;
  EXPECT_NE(d.message.find("the list that '[' opens at line 1, column 4"), std::string::npos)
      << d.message;
}

TEST(YamlTree, OnlyTheFirstDocumentIsRead) {
  const YamlTree tree = parse_yaml("a: 1\n---\nb: [\n", "t.yaml", kDepth);
  ASSERT_EQ(tree.root().size(), 1u);
  EXPECT_EQ(tree.root().entries()[0].key->text(), "a");
}

TEST(YamlTree, NestingUpToTheLimitIsRead) {
  const YamlTree tree = parse_yaml(std::string(3, '[') + std::string(3, ']'), "t.yaml", 3);
  EXPECT_TRUE(tree.root().items()[0]->items()[0]->is_sequence());
}

TEST(YamlTree, NestingBeyondTheLimitIsRefusedWhereItBegins) {
  const Diagnostic d = refusal_of("a:\n  b: [[x]]\n", 3);
  EXPECT_EQ(d.location.line, 2);
  EXPECT_EQ(d.location.column, 7);  // the second `[`, the fourth level
  EXPECT_NE(d.message.find("the limit of 3 levels"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("(LoadLimits::max_nesting_depth)"), std::string::npos) << d.message;
}

TEST(YamlTree, HostileNestingIsRefusedWithoutRecursion) {
  // A reader that recursed once per level would overflow the stack on 100 000 levels.
  for (const std::string& text : {std::string(100'000, '['), std::string(100'000, '{'), [] {
                                    std::string items;
                                    for (int i = 0; i < 100'000; ++i) items += "- ";
                                    return items + "x\n";
                                  }()}) {
    const Diagnostic d = refusal_of(text);
    EXPECT_NE(d.message.find("the limit of 64 levels"), std::string::npos) << d.message;
  }
}

}  // namespace
}  // namespace stiffmsa::detail
