#pragma once
// A family of models of one topology whose numbers depend on named parameters: a parametric
// model file (its `parameters:` and expressions), or a function of the caller's that builds
// a Model from parameter values. Sweeps (sweep.hpp) solve one member per pose.
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "stiffmsa/model.hpp"
#include "stiffmsa/result.hpp"

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
  // Writes into `member` the member for one value per parameter, in parameter order; throws
  // InputError when those values make an invalid model (`member` then holds no valid member;
  // the next call writes a valid one over it). The caller hands one builder the same model at every call
  // and changes it in no other way in between (a model shared by two builders breaks this):
  // a builder may then keep in it what all members share and write only the numbers that
  // differ, so that a sweep builds its members without copying the model. Any model other than
  // the one of its previous call, an empty one at the first call for instance, is filled
  // whole. A builder may keep caches between calls and is used by one thread at a time; each
  // thread of a sweep makes its own.
  using Builder = std::function<void(std::span<const double> values, Model& member)>;
  using BuilderFactory = std::function<Builder()>;

  ModelFamily(std::string name, std::vector<Parameter> parameters, BuilderFactory make_builder);

  const std::string& name() const { return name_; }
  const std::vector<Parameter>& parameters() const { return parameters_; }
  std::optional<std::size_t> find_parameter(const std::string& name) const;
  std::vector<double> default_values() const;
  // The parameters at their defaults, as a result records them (Result::parameters).
  std::vector<ParameterValue> parameter_values() const;

  // The same family with other defaults (one value per parameter): the values that the
  // parameters a sweep does not vary keep.
  ModelFamily with_defaults(std::span<const double> values) const;

  // A builder of the family's members; it throws UsageError when not given one value per
  // parameter.
  Builder make_builder() const;
  // One member; for many, make a builder once.
  Model build(std::span<const double> values) const;

 private:
  std::string name_;
  std::vector<Parameter> parameters_;
  BuilderFactory make_builder_;
};

}  // namespace stiffmsa
