#include "stiffmsa/structure.hpp"

#include <algorithm>

#include "model/model_numbers.hpp"
#include "model/structure_impl.hpp"

namespace stiffmsa {

namespace {

Model validated(Model model) {
  const detail::ModelIndex index(model);
  detail::validate(model, index);
  return model;
}

}  // namespace

Structure::Impl::Impl(Model validated_model)
    : model(std::move(validated_model)),
      index(model),
      topology(detail::build_topology(model, index)) {
  detail::for_each_number(model, [&](const double&) { ++value_count; });
}

Structure::Impl::Impl(const Impl& other, std::span<const double> values)
    : model(other.model), index(model), topology(other.topology), value_count(other.value_count) {
  if (values.size() != value_count)
    throw UsageError("the structure has " + std::to_string(value_count) + " value slots; got " +
                     std::to_string(values.size()) + " values");
  const double* next = values.data();
  detail::for_each_number(model, [&](double& v) { v = *next++; });
}

const std::vector<std::string>& Structure::Impl::names() const {
  std::call_once(named, [&] {
    slot_names.reserve(value_count);
    detail::for_each_named_number(model, [&](const double&, const detail::SlotName& name) {
      slot_names.push_back(name.str());
    });
  });
  return slot_names;
}

Structure::Structure(Model model)
    : impl_(std::make_shared<const Impl>(validated(std::move(model)))) {}

const Model& Structure::model() const { return impl_->model; }
std::size_t Structure::value_count() const { return impl_->value_count; }
const std::vector<std::string>& Structure::slot_names() const { return impl_->names(); }

std::optional<std::size_t> Structure::find_slot(std::string_view name) const {
  const auto& names = impl_->names();
  const auto found = std::find(names.begin(), names.end(), name);
  if (found == names.end()) return std::nullopt;
  return static_cast<std::size_t>(found - names.begin());
}

std::vector<double> Structure::default_values() const {
  std::vector<double> values;
  values.reserve(value_count());
  detail::for_each_number(impl_->model, [&](const double& v) { values.push_back(v); });
  return values;
}

namespace {
void require_value_count(std::size_t expected, std::size_t given) {
  if (given != expected)
    throw UsageError("the structure has " + std::to_string(expected) + " value slots; got " +
                     std::to_string(given) + " values");
}
}  // namespace

std::vector<double> Structure::values_of(const Model& model) const {
  if (!detail::same_structure(model, impl_->model))
    throw InputError(
        {}, "",
        "the model's structure differs from that the analysis was set up for (in a sweep: the "
        "model "
        "at the parameters' defaults): an entity was added, removed, renamed or reconnected, "
        "changed "
        "its kind or which optional numbers it gives; one structure takes models of one topology "
        "that differ in their numbers only");
  std::vector<double> values;
  values.reserve(value_count());
  detail::for_each_number(model, [&](const double& v) { values.push_back(v); });
  return values;
}

void Structure::write_values(std::span<const double> values, Model& model) const {
  require_value_count(value_count(), values.size());
  const double* next = values.data();
  detail::for_each_number(model, [&](double& v) { v = *next++; });
}

Model Structure::model_with(std::span<const double> values) const {
  Model model = impl_->model;
  write_values(values, model);
  return model;
}

Structure Structure::with_default_values(std::span<const double> values) const {
  Structure changed = *this;
  changed.impl_ = std::make_shared<const Impl>(*impl_, values);
  return changed;
}

std::vector<Diagnostic> Structure::find_value_defects(std::span<const double> values) const {
  return detail::find_value_defects(model_with(values), impl_->index);
}

namespace detail {

namespace {

bool same_connection(const Connection& a, const Connection& b) {
  const auto dims = [](const std::optional<MatX>& m) {
    return m ? std::pair{m->rows(), m->cols()} : std::pair{Eigen::Index{-1}, Eigen::Index{-1}};
  };
  return a.kinematics.type == b.kinematics.type &&
         a.kinematics.free_rows.size() == b.kinematics.free_rows.size() &&
         dims(a.stiffness) == dims(b.stiffness) && a.preload.has_value() == b.preload.has_value() &&
         (!a.preload || a.preload->size() == b.preload->size()) && a.is_actuated == b.is_actuated;
}

bool same_link_kind(const LinkKind& a, const LinkKind& b) {
  if (a.index() != b.index()) return false;
  if (const auto* beam = std::get_if<BeamLink>(&a)) {
    const auto& other = std::get<BeamLink>(b);
    return beam->material.nu.has_value() == other.material.nu.has_value() &&
           beam->material.G.has_value() == other.material.G.has_value() &&
           beam->material.density.has_value() == other.material.density.has_value() &&
           beam->section.shape == other.section.shape &&
           beam->section.Asy.has_value() == other.section.Asy.has_value() &&
           beam->section.Asz.has_value() == other.section.Asz.has_value() &&
           beam->shear == other.shear && beam->zref.has_value() == other.zref.has_value();
  }
  if (const auto* matrix = std::get_if<MatrixLink>(&a)) {
    const auto& other = std::get<MatrixLink>(b);
    return matrix->frame == other.frame && matrix->zref.has_value() == other.zref.has_value();
  }
  if (const auto* compliance = std::get_if<ComplianceLink>(&a)) {
    const auto& other = std::get<ComplianceLink>(b);
    return compliance->frame == other.frame &&
           compliance->zref.has_value() == other.zref.has_value();
  }
  return true;
}

template <class T, class Same>
bool all_same(const std::vector<T>& a, const std::vector<T>& b, Same&& same) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}

bool same_load(const Load& l, const Load& m) {
  return l.at == m.at && l.link == m.link && l.self_weight == m.self_weight;
}

// A load along a link is distributed or a point load; which one decides its value slots.
bool same_link_load(const LinkLoad& l, const LinkLoad& m) {
  return l.link == m.link && l.load.index() == m.load.index();
}

bool same_load_case(const LoadCase& c, const LoadCase& d) {
  return c.name == d.name && all_same(c.loads, d.loads, same_load) &&
         all_same(c.link_loads, d.link_loads, same_link_load) &&
         c.gravity.has_value() == d.gravity.has_value();
}

}  // namespace

bool same_structure(const Model& a, const Model& b) {
  return a.options.accept_idle_motions == b.options.accept_idle_motions &&
         a.options.mode == b.options.mode && a.options.load_steps == b.options.load_steps &&
         all_same(a.points, b.points,
                  [](const Point& p, const Point& q) { return p.name == q.name; }) &&
         all_same(a.links, b.links,
                  [](const Link& l, const Link& m) {
                    return l.name == m.name && l.from == m.from && l.to == m.to &&
                           same_link_kind(l.kind, m.kind);
                  }) &&
         all_same(a.joints, b.joints,
                  [](const Joint& j, const Joint& k) {
                    return j.name == k.name && j.at == k.at && j.links == k.links &&
                           same_connection(j.connection, k.connection);
                  }) &&
         all_same(a.supports, b.supports,
                  [](const Support& s, const Support& t) {
                    return s.name == t.name && s.at == t.at && s.links == t.links &&
                           same_connection(s.connection, t.connection) &&
                           s.displacement.has_value() == t.displacement.has_value();
                  }) &&
         all_same(a.loads, b.loads, same_load) &&
         all_same(a.link_loads, b.link_loads, same_link_load) &&
         a.gravity.has_value() == b.gravity.has_value() &&
         all_same(a.load_cases, b.load_cases, same_load_case) &&
         all_same(a.end_effectors, b.end_effectors, [](const EndEffector& e, const EndEffector& f) {
           return e.name == f.name && e.at == f.at && e.link == f.link &&
                  e.axes.has_value() == f.axes.has_value();
         });
}

}  // namespace detail

}  // namespace stiffmsa
