#include "stiffmsa/parametric.hpp"

#include "stiffmsa/number_text.hpp"

namespace stiffmsa {

ModelFamily::ModelFamily(std::string name, std::vector<Parameter> parameters,
                         BuilderFactory make_builder)
    : name_(std::move(name)), parameters_(std::move(parameters)), make_builder_(std::move(make_builder)) {}

std::optional<std::size_t> ModelFamily::find_parameter(const std::string& name) const {
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (parameters_[i].name == name) return i;
  return std::nullopt;
}

namespace {
// One value per parameter, or a UsageError that says how many.
void check_value_count(const std::string& model, std::size_t parameters, std::size_t values) {
  if (values != parameters)
    throw UsageError("the model '" + model + "' has " + counted(parameters, "parameter") + "; got " +
                     counted(values, "value"));
}
}  // namespace

std::vector<double> ModelFamily::default_values() const {
  std::vector<double> values;
  values.reserve(parameters_.size());
  for (const auto& p : parameters_) values.push_back(p.default_value);
  return values;
}

std::vector<ParameterValue> ModelFamily::parameter_values() const {
  std::vector<ParameterValue> values;
  values.reserve(parameters_.size());
  for (const auto& p : parameters_) values.push_back({p.name, p.default_value, p.unit, p.set});
  return values;
}

ModelFamily::Builder ModelFamily::make_builder() const {
  return [count = parameters_.size(), name = name_, build = make_builder_()](std::span<const double> values,
                                                                             Model& member) mutable {
    check_value_count(name, count, values.size());
    build(values, member);
  };
}

Model ModelFamily::build(std::span<const double> values) const {
  Model member;
  make_builder()(values, member);
  return member;
}

ModelFamily ModelFamily::with_defaults(std::span<const double> values) const {
  check_value_count(name_, parameters_.size(), values.size());
  ModelFamily changed = *this;
  for (std::size_t i = 0; i < values.size(); ++i) {
    Parameter& p = changed.parameters_[i];
    p.set = p.set || values[i] != p.default_value;
    p.default_value = values[i];
  }
  return changed;
}

}  // namespace stiffmsa
