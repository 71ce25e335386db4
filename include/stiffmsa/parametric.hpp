#pragma once
// A family of models of one structure whose numbers depend on named parameters: a parametric
// model file (its `parameters:` and expressions), or a plain function of the caller's that
// returns a Model for parameter values. A family has one Structure (structure.hpp); a member
// is a set of values for its slots. Sweeps (sweep.hpp) solve one member per pose.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "stiffmsa/model.hpp"
#include "stiffmsa/structure.hpp"

namespace stiffmsa {

struct Parameter {
  std::string name;
  double default_value = 0;
  std::string unit;  // as the file gives it, for labels; may be empty
  SourceLocation location;
  // The default was replaced by the user's setting (load_model_family's `settings`, the
  // command's --set) or by with_defaults(): results and plots say so.
  bool set = false;
};

class ModelFamily {
 public:
  // Writes a member's values (one per slot of the family's structure, in slot order) for one
  // value per parameter, in parameter order, and replaces `warnings` by what the member's
  // reader noticed that does not make it invalid (Model::warnings: a robot's joint position
  // outside its limits); throws InputError when the parameter values give no member (an
  // expression that cannot be evaluated there, say). The values are checked by the solve, not
  // here. A writer may keep caches between calls and is used by one thread at a time; each
  // thread of a sweep makes its own.
  using ValueWriter =
      std::function<void(std::span<const double> parameters, std::span<double> values,
                         std::vector<Diagnostic>& warnings)>;
  using ValueWriterFactory = std::function<ValueWriter()>;
  // A member as a model, for one value per parameter.
  using MemberFunction = std::function<Model(std::span<const double> parameters)>;

  // A family whose members' values are written straight into the structure's slots (a model
  // file's expressions bound to them when it was read).
  ModelFamily(std::string name, std::vector<Parameter> parameters, Structure structure,
              ValueWriterFactory make_writer);
  // A family of a plain function: the member at the defaults fixes the structure (made when a
  // structure is first needed); every member must have it (InputError otherwise).
  ModelFamily(std::string name, std::vector<Parameter> parameters, MemberFunction member);

  const std::string& name() const { return name_; }
  const std::vector<Parameter>& parameters() const { return parameters_; }
  // The index of the parameter of that name, if there is one.
  std::optional<std::size_t> find_parameter(const std::string& name) const;
  // The index of the parameter of that name; NameError when there is none, whose message names
  // the family, its file where it was read from one, and the nearest parameter.
  std::size_t parameter_index(const std::string& name) const;
  std::vector<double> default_values() const;
  // The parameters at their defaults, as a result records them (Result::parameters).
  std::vector<ParameterValue> parameter_values() const;

  // The same family with other defaults (one value per parameter): the values that the
  // parameters a sweep does not vary keep.
  ModelFamily with_defaults(std::span<const double> values) const;

  // The family's structure. Throws InputError when the member at the defaults is invalid.
  Structure structure() const;
  // A writer of the members' values into the slots of `structure`, which structure() made; it
  // throws UsageError when not given one value per parameter or one per slot.
  ValueWriter make_writer(const Structure& structure) const;
  // One member as a model, validated (InputError names what is wrong). For many, write values
  // with one writer and solve them with one workspace.
  Model build(std::span<const double> values) const;

 private:
  std::string name_;
  std::vector<Parameter> parameters_;
  // Of a file family; a function family makes its structure from its member at the defaults.
  std::optional<Structure> structure_;
  ValueWriterFactory make_writer_;
  MemberFunction member_;
};

}  // namespace stiffmsa
