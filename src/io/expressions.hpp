#pragma once
// Expressions of a parametric model file (muparser syntax): one evaluator per model builder,
// holding each distinct expression compiled once, so that building the next member of a
// family only re-evaluates. An evaluator is used by one thread at a time.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace mu {
class Parser;
}

namespace stiffmsa::detail {

// Why `name` cannot be a parameter's name (nullopt when it can): the letters, digits and
// underscores of an identifier, not one of the expression library's functions or constants.
std::optional<std::string> parameter_name_problem(const std::string& name);

// The names an expression may use are the parameters, then the derived values: named
// expressions that the file computes in order from the parameters and the derived values
// before them (inverse kinematics written once and used by several numbers).
class ExpressionEvaluator {
 public:
  ExpressionEvaluator(std::vector<std::string> parameter_names,
                      std::vector<std::string> derived_names);
  ~ExpressionEvaluator();
  ExpressionEvaluator(const ExpressionEvaluator&) = delete;
  ExpressionEvaluator& operator=(const ExpressionEvaluator&) = delete;

  // One value per parameter, in the order of the names.
  void set_values(std::span<const double> values);

  struct Outcome {
    double value = 0;
    std::string error;  // empty on success: a sentence naming what is wrong
    // The error only repeats one already reported: the expression uses a derived value that
    // could not be computed.
    bool follows_earlier_error = false;
  };
  // The value of `text` for the current parameter values. A syntax error, an unknown name
  // or a value that is not finite is an error that names the parameters involved.
  Outcome evaluate(const std::string& text);
  // Evaluates derived value `index` (0-based among the derived values) and keeps it for the
  // expressions that use it; it may use only the derived values before it.
  Outcome evaluate_derived(std::size_t index, const std::string& text);

 private:
  struct Compiled;
  Compiled& compile(const std::string& text);
  // Parses `text` into `compiled`, or records why it cannot be evaluated.
  void set_up(Compiled& compiled, const std::string& text);
  std::string inputs_of(const Compiled& compiled) const;

  std::vector<std::string> names_;  // parameters, then derived values
  std::size_t parameter_count_;
  std::unique_ptr<double[]> values_;  // muparser reads the parameters through these addresses
  std::unordered_map<std::string, std::unique_ptr<Compiled>> compiled_;
  std::unique_ptr<Compiled> scratch_;  // the latest expression beyond those kept
  // The kept expressions in the order asked since the last set_values: each member of a family
  // asks for the same texts in the same order, so the next member finds each at its place with
  // one comparison of its text instead of a search of compiled_ (which hashes or compares the
  // text against every entry: ~470 instructions a lookup, as much as muparser's evaluation).
  struct Asked {
    const std::string* text;  // the key in compiled_
    Compiled* compiled;
  };
  std::vector<Asked> asked_;
  std::size_t next_asked_ = 0;
};

}  // namespace stiffmsa::detail
