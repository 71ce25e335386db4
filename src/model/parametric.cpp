#include "stiffmsa/parametric.hpp"

namespace stiffmsa {

ModelFamily::ModelFamily(std::string name, std::vector<Parameter> parameters,
                         BuilderFactory make_builder)
    : name_(std::move(name)), parameters_(std::move(parameters)), make_builder_(std::move(make_builder)) {}

std::optional<std::size_t> ModelFamily::find_parameter(const std::string& name) const {
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (parameters_[i].name == name) return i;
  return std::nullopt;
}

std::vector<double> ModelFamily::default_values() const {
  std::vector<double> values;
  values.reserve(parameters_.size());
  for (const auto& p : parameters_) values.push_back(p.default_value);
  return values;
}

ModelFamily::Builder ModelFamily::make_builder() const {
  return [count = parameters_.size(), name = name_, build = make_builder_()](std::span<const double> values) mutable {
    if (values.size() != count)
      throw UsageError("the model '" + name + "' has " + std::to_string(count) + " parameters; got " +
                       std::to_string(values.size()) + " values");
    return build(values);
  };
}

ModelFamily ModelFamily::with_defaults(std::span<const double> values) const {
  if (values.size() != parameters_.size())
    throw UsageError("the model '" + name_ + "' has " + std::to_string(parameters_.size()) +
                     " parameters; got " + std::to_string(values.size()) + " values");
  ModelFamily changed = *this;
  for (std::size_t i = 0; i < values.size(); ++i) changed.parameters_[i].default_value = values[i];
  return changed;
}

}  // namespace stiffmsa
