#include "io/expressions.hpp"

#include <muParser.h>

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "model/suggest.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa::detail {

namespace {

// muparser reads `x = 1` as an assignment to x, which would change a parameter for every
// expression evaluated after it; a number only computes a value. (`==`, `<=`, `>=` and `!=`
// compare.)
bool assigns(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '=') continue;
    const char before = i > 0 ? text[i - 1] : ' ';
    const char after = i + 1 < text.size() ? text[i + 1] : ' ';
    if (after == '=') {
      ++i;
      continue;
    }
    if (before != '<' && before != '>' && before != '!' && before != '=') return true;
  }
  return false;
}

bool is_identifier(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

}  // namespace

std::optional<std::string> parameter_name_problem(const std::string& name) {
  if (!is_identifier(name))
    return "'" + name +
           "' cannot be a parameter's name: a name starts with a letter and has only letters, "
           "digits and underscores";
  // Asked for every name of every member a sweep builds: the library's names are read once.
  struct ReservedNames {
    std::set<std::string> functions, constants;
  };
  static const ReservedNames reserved = [] {
    const mu::Parser reference;
    ReservedNames names;
    for (const auto& entry : reference.GetFunDef()) names.functions.insert(entry.first);
    for (const auto& entry : reference.GetConst()) names.constants.insert(entry.first);
    return names;
  }();
  if (reserved.functions.count(name) > 0)
    return "'" + name + "' cannot be a parameter's name: it is a function of the expressions";
  if (reserved.constants.count(name) > 0)
    return "'" + name + "' cannot be a parameter's name: it is a constant of the expressions";
  return std::nullopt;
}

struct ExpressionEvaluator::Compiled {
  mu::Parser parser;
  std::string error;  // a syntax error found when compiling, reported at every evaluation
  // Per name in names_, whether the expression reads it; empty until first asked (the order of
  // derived values, a failed evaluation's message): muparser finds the names by parsing the text
  // once more, so they are asked once and only where needed.
  std::vector<bool> uses;
};

namespace {

const std::vector<bool>& names_used(mu::Parser& parser, const std::vector<std::string>& names,
                                    std::vector<bool>& uses) {
  if (uses.size() == names.size()) return uses;
  const auto& used = parser.GetUsedVar();  // the next Eval() parses again
  uses.assign(names.size(), false);
  for (std::size_t i = 0; i < names.size(); ++i) uses[i] = used.count(names[i]) > 0;
  return uses;
}

}  // namespace

ExpressionEvaluator::ExpressionEvaluator(std::vector<std::string> parameter_names,
                                         std::vector<std::string> derived_names)
    : names_(std::move(parameter_names)), parameter_count_(names_.size()) {
  names_.insert(names_.end(), derived_names.begin(), derived_names.end());
  values_.reset(new double[names_.size()]());
}

ExpressionEvaluator::~ExpressionEvaluator() = default;

void ExpressionEvaluator::set_values(std::span<const double> values) {
  for (std::size_t i = 0; i < parameter_count_ && i < values.size(); ++i) values_[i] = values[i];
  next_asked_ = 0;
}

ExpressionEvaluator::Compiled& ExpressionEvaluator::compile(const std::string& text) {
  if (next_asked_ < asked_.size() && *asked_[next_asked_].text == text)
    return *asked_[next_asked_++].compiled;
  // A compiled expression takes about 6 KB and 30 µs to set up. A real model has tens of
  // distinct expressions; a huge generated file can have millions, whose parsers are then not
  // kept (each evaluation parses again) rather than filling the memory.
  constexpr std::size_t max_kept = 20'000;
  const auto remember = [&](const std::string& key, Compiled& compiled) -> Compiled& {
    if (next_asked_ < max_kept) {
      asked_.resize(next_asked_);  // the order changed here: what followed is not known
      asked_.push_back({&key, &compiled});
      ++next_asked_;
    }
    return compiled;
  };
  if (const auto found = compiled_.find(text); found != compiled_.end())
    return remember(found->first, *found->second);
  if (compiled_.size() >= max_kept) {
    scratch_ = std::make_unique<Compiled>();
    set_up(*scratch_, text);
    return *scratch_;
  }
  const auto added = compiled_.emplace(text, std::make_unique<Compiled>()).first;
  set_up(*added->second, text);
  return remember(added->first, *added->second);
}

void ExpressionEvaluator::set_up(Compiled& compiled, const std::string& text) {
  if (assigns(text)) {
    compiled.error =
        "the expression '" + text +
        "' assigns a value with '='; an expression only computes a number (compare with '==')";
    return;
  }
  try {
    // muparser built by GCC rounds its _pi to 13 digits (a speed trade of its own); angles
    // in a stiffness model need every digit.
    compiled.parser.DefineConst("_pi", std::numbers::pi);
    compiled.parser.DefineConst("_e", std::numbers::e);
    for (std::size_t i = 0; i < names_.size(); ++i)
      compiled.parser.DefineVar(names_[i], &values_[i]);
    compiled.parser.SetExpr(text);
    compiled.parser.Eval();  // parses now, so that syntax errors are found once
    if (compiled.parser.GetNumResults() != 1)
      compiled.error =
          "the expression '" + text + "' gives several values; a number takes one expression";
  } catch (const mu::Parser::exception_type& e) {
    if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN && is_identifier(e.GetToken())) {
      compiled.error = "unknown parameter '" + e.GetToken() + "' in the expression '" + text + "'" +
                       suggestion(e.GetToken(), names_, "the names are");
      if (names_.empty()) compiled.error += "; the file declares no `parameters:`";
    } else {
      compiled.error = "cannot read the expression '" + text + "': " + e.GetMsg();
    }
  }
}

// "x = 0.3, L = 0.2": the parameters an expression reads, with their current values.
std::string ExpressionEvaluator::inputs_of(const Compiled& compiled) const {
  std::string text;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (!compiled.uses[i]) continue;
    if (!text.empty()) text += ", ";
    text += names_[i] + " = " + shortest_text(values_[i]);
  }
  return text;
}

ExpressionEvaluator::Outcome ExpressionEvaluator::evaluate_derived(std::size_t index,
                                                                   const std::string& text) {
  const std::size_t slot = parameter_count_ + index;
  Compiled& compiled = compile(text);
  std::size_t last_name_used = 0;  // 1 + the index in names_ of the last name it uses
  if (compiled.error.empty()) {
    const std::vector<bool>& uses = names_used(compiled.parser, names_, compiled.uses);
    for (std::size_t i = 0; i < uses.size(); ++i)
      if (uses[i]) last_name_used = i + 1;
  }
  if (last_name_used > slot) {
    const std::size_t later = last_name_used - 1;
    return {0, "the expression '" + text + "' uses '" + names_[later] + "', which is " +
                   (later == slot ? std::string("this derived value itself")
                                  : "derived later in the file") +
                   "; derived values are computed in the order of the file"};
  }
  Outcome outcome = evaluate(text);
  values_[slot] = outcome.error.empty() ? outcome.value : std::numeric_limits<double>::quiet_NaN();
  return outcome;
}

ExpressionEvaluator::Outcome ExpressionEvaluator::evaluate(const std::string& text) {
  Compiled& compiled = compile(text);
  if (!compiled.error.empty()) return {0, compiled.error, false};
  double value = 0;
  try {
    value = compiled.parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    return {0, "cannot evaluate the expression '" + text + "': " + e.GetMsg(), false};
  }
  if (std::isfinite(value)) return {value, {}, false};
  const std::vector<bool>& uses = names_used(compiled.parser, names_, compiled.uses);
  bool uses_failed_value = false;
  for (std::size_t i = parameter_count_; i < names_.size(); ++i)
    uses_failed_value = uses_failed_value || (std::isnan(values_[i]) && uses[i]);
  const std::string inputs = inputs_of(compiled);
  return {0,
          "the expression '" + text + "' gives " + shortest_text(value) +
              (inputs.empty() ? std::string() : " for " + inputs) + ", not a finite number",
          uses_failed_value};
}

}  // namespace stiffmsa::detail
