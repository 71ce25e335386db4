#include "stiffmsa/parametric.hpp"

#include "model/name_errors.hpp"
#include "model/suggest.hpp"
#include "stiffmsa/number_text.hpp"
#include "stiffmsa/validate.hpp"

namespace stiffmsa {

ModelFamily::ModelFamily(std::string name, std::vector<Parameter> parameters, Structure structure,
                         ValueWriterFactory make_writer)
    : name_(std::move(name)),
      parameters_(std::move(parameters)),
      structure_(std::move(structure)),
      make_writer_(std::move(make_writer)) {}

ModelFamily::ModelFamily(std::string name, std::vector<Parameter> parameters, MemberFunction member)
    : name_(std::move(name)), parameters_(std::move(parameters)), member_(std::move(member)) {}

std::optional<std::size_t> ModelFamily::find_parameter(const std::string& name) const {
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (parameters_[i].name == name) return i;
  return std::nullopt;
}

std::size_t ModelFamily::parameter_index(const std::string& name) const {
  if (const auto index = find_parameter(name)) return *index;
  std::vector<std::string> names;
  names.reserve(parameters_.size());
  for (const auto& p : parameters_) names.push_back(p.name);
  const std::string file = structure_ ? structure_->model().source_file : std::string();
  throw detail::NameErrorInContext("parameter", name, names,
                                   detail::no_parameter_message(name_, file, name, names));
}

namespace {
// One value per parameter, or a UsageError that says how many.
void check_value_count(const std::string& model, std::size_t parameters, std::size_t values) {
  if (values != parameters)
    throw UsageError("the model '" + model + "' has " + counted(parameters, "parameter") +
                     "; got " + counted(values, "value"));
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

Structure ModelFamily::structure() const {
  if (structure_) return *structure_;
  return Structure(build(default_values()));
}

ModelFamily::ValueWriter ModelFamily::make_writer(const Structure& structure) const {
  const std::size_t count = parameters_.size(), slots = structure.value_count();
  const auto check_counts = [name = name_, count, slots](std::span<const double> parameters,
                                                         std::span<double> values) {
    check_value_count(name, count, parameters.size());
    if (values.size() != slots)
      throw UsageError("the model '" + name + "' has " + counted(slots, "value slot") +
                       "; got room for " + counted(values.size(), "value"));
  };
  if (structure_)
    return [check_counts, write = make_writer_()](std::span<const double> parameters,
                                                  std::span<double> values,
                                                  std::vector<Diagnostic>& warnings) mutable {
      check_counts(parameters, values);
      write(parameters, values, warnings);
    };
  return [check_counts, structure, member = member_](std::span<const double> parameters,
                                                     std::span<double> values,
                                                     std::vector<Diagnostic>& warnings) {
    check_counts(parameters, values);
    Model built = member(parameters);
    const std::vector<double> written = structure.values_of(built);
    std::copy(written.begin(), written.end(), values.begin());
    warnings = std::move(built.warnings);
  };
}

Model ModelFamily::build(std::span<const double> values) const {
  check_value_count(name_, parameters_.size(), values.size());
  Model member;
  if (structure_) {
    std::vector<double> slots(structure_->value_count());
    std::vector<Diagnostic> warnings;
    make_writer_()(values, slots, warnings);
    // The structure was validated when the file was read: its values alone are new here.
    auto defects = structure_->find_value_defects(slots);
    if (!defects.empty()) throw InputError(std::move(defects));
    member = structure_->model_with(slots);
    member.warnings = std::move(warnings);
  } else {
    member = member_(values);
    validate(member);
  }
  for (std::size_t i = 0; i < values.size() && i < member.parameters.size(); ++i)
    member.parameters[i].value = values[i];
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
