#include "analysis/case_loads.hpp"

#include <algorithm>
#include <cmath>

#include "elements/beam_element.hpp"
#include "elements/finite_rotation.hpp"
#include "elements/loaded_blocks.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa::detail {

namespace {

// The stations of a loaded beam's internal forces besides its point loads' positions.
constexpr int kEvenStations = 11;

bool weighs(const Link& link) {
  const auto* beam = std::get_if<BeamLink>(&link.kind);
  return beam && beam->material.density && *beam->material.density != 0;
}

bool gravity_weighs(const std::optional<Vec3>& gravity, const Model& model) {
  return gravity && !gravity->isZero(0) &&
         std::any_of(model.links.begin(), model.links.end(), weighs);
}

const Vec3& end_position(const Model& model, const Topology& topology, int end) {
  return model.points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(end)])]
      .position;
}

// The link's local axes (rows, global components), as its block uses them.
Mat3 axes_of(const BeamLink& beam, const Vec3& from, const Vec3& to) {
  return link_axes(from, to, beam.zref);
}

BeamLoad local_load(const Mat3& axes,
                    const std::variant<DistributedLinkLoad, PointLinkLoad>& load) {
  if (const auto* distributed = std::get_if<DistributedLinkLoad>(&load))
    return DistributedLoad{axes * distributed->from, axes * distributed->to};
  const auto& point = std::get<PointLinkLoad>(load);
  return PointLoad{axes * point.force, axes * point.moment, point.position};
}

// The wrench a clamp at each end exerts on the link under the load (global, about each end's
// point): the exact fixed-end forces for a beam; for any other link the load's resultant shared
// between the ends by the lever rule, negated (the statically equivalent end loads of a
// simply supported span), which the link's own stiffness, if any, does not see along its length.
std::pair<Vec6, Vec6> clamp_wrenches(const Model& model, const Topology& topology,
                                     const ResolvedLinkLoad& load) {
  const Link& link = model.links[static_cast<std::size_t>(load.link)];
  const Vec3& from = end_position(model, topology, 2 * load.link);
  const Vec3& to = end_position(model, topology, 2 * load.link + 1);
  const double length = (to - from).norm();
  if (const auto* beam = std::get_if<BeamLink>(&link.kind)) {
    const Mat3 axes = axes_of(*beam, from, to);
    const Vec12 local =
        beam_fixed_end_forces(beam_constants(*beam, length), local_load(axes, load.load));
    Vec6 at_from, at_to;
    at_from << axes.transpose() * local.segment<3>(0), axes.transpose() * local.segment<3>(3);
    at_to << axes.transpose() * local.segment<3>(6), axes.transpose() * local.segment<3>(9);
    return {at_from, at_to};
  }
  Vec6 at_from = Vec6::Zero(), at_to = Vec6::Zero();
  if (const auto* distributed = std::get_if<DistributedLinkLoad>(&load.load)) {
    at_from.head<3>() = -length * (2 * distributed->from + distributed->to) / 6;
    at_to.head<3>() = -length * (distributed->from + 2 * distributed->to) / 6;
  } else {
    const auto& point = std::get<PointLinkLoad>(load.load);
    at_from << -(1 - point.position) * point.force, -point.moment;
    at_to.head<3>() = -point.position * point.force;
  }
  return {at_from, at_to};
}

void require_position(const LinkLoad& load, const std::string& where) {
  const auto* point = std::get_if<PointLinkLoad>(&load.load);
  if (point && !(point->position >= 0 && point->position <= 1))
    throw InputError(load.origin.of("position"), where,
                     "a point load's position must be a fraction of the link's length in [0, 1], "
                     "got " +
                         shortest_text(point->position));
}

CaseLoads make_case(const Model& model, const Topology& topology, std::string name,
                    const std::vector<Load>& loads, const std::vector<int>& load_ends,
                    const std::vector<LinkLoad>& link_loads, const std::vector<int>& load_links,
                    const std::optional<Vec3>& gravity, const std::string& where) {
  CaseLoads c;
  c.name = std::move(name);
  c.external.assign(static_cast<std::size_t>(topology.end_count()), Vec6::Zero());
  for (std::size_t i = 0; i < loads.size(); ++i) {
    c.external[static_cast<std::size_t>(load_ends[i])] += loads[i].wrench;
    c.loaded |= !loads[i].wrench.isZero(0);
  }
  for (std::size_t i = 0; i < link_loads.size(); ++i) {
    require_position(link_loads[i], where);
    c.link_loads.push_back({load_links[i], link_loads[i].load});
  }
  if (gravity && !gravity->isZero(0))
    for (std::size_t l = 0; l < model.links.size(); ++l)
      if (weighs(model.links[l])) {
        const auto& beam = std::get<BeamLink>(model.links[l].kind);
        const Vec3 weight = *beam.material.density * section_properties(beam.section).A * *gravity;
        c.link_loads.push_back({static_cast<int>(l), DistributedLinkLoad{weight, weight}});
      }
  if (c.link_loads.empty()) return c;
  c.end_loads = c.external;
  c.fixed_end.assign(c.external.size(), Vec6::Zero());
  for (const ResolvedLinkLoad& load : c.link_loads) {
    const auto [at_from, at_to] = clamp_wrenches(model, topology, load);
    const auto from = static_cast<std::size_t>(2 * load.link);
    c.fixed_end[from] += at_from;
    c.fixed_end[from + 1] += at_to;
    c.external[from] -= at_from;
    c.external[from + 1] -= at_to;
    c.loaded |= !at_from.isZero(0) || !at_to.isZero(0);
  }
  return c;
}

}  // namespace

bool has_unnamed_case(const Model& model) {
  return !model.loads.empty() || !model.link_loads.empty() || model.gravity.has_value() ||
         model.load_cases.empty();
}

bool loads_along_links(const Model& model) {
  if (!model.link_loads.empty() || gravity_weighs(model.gravity, model)) return true;
  return std::any_of(model.load_cases.begin(), model.load_cases.end(), [&](const LoadCase& c) {
    return !c.link_loads.empty() || gravity_weighs(c.gravity, model);
  });
}

std::vector<CaseLoads> case_loads(const Model& model, const Topology& topology) {
  std::vector<CaseLoads> cases;
  cases.reserve(model.load_cases.size() + 2);
  if (has_unnamed_case(model))
    cases.push_back(make_case(model, topology, "", model.loads, topology.load_ends,
                              model.link_loads, topology.link_load_links, model.gravity, "loads"));
  for (std::size_t i = 0; i < model.load_cases.size(); ++i) {
    const LoadCase& c = model.load_cases[i];
    cases.push_back(make_case(model, topology, c.name, c.loads, topology.case_load_ends[i],
                              c.link_loads, topology.case_link_load_links[i], c.gravity,
                              "load_cases." + c.name));
  }
  if (std::any_of(model.loads.begin(), model.loads.end(),
                  [](const Load& l) { return l.self_weight; })) {
    std::vector<Load> weight;
    std::vector<int> ends;
    for (std::size_t i = 0; i < model.loads.size(); ++i)
      if (model.loads[i].self_weight) {
        weight.push_back(model.loads[i]);
        ends.push_back(topology.load_ends[i]);
      }
    CaseLoads c = make_case(model, topology, "", weight, ends, {}, {}, std::nullopt, "loads");
    c.with_state = false;
    cases.push_back(std::move(c));
  }
  return cases;
}

LoadResultant resultant(const Model& model, const Topology& topology,
                        const ResolvedLinkLoad& load) {
  const Vec3& from = end_position(model, topology, 2 * load.link);
  const Vec3& to = end_position(model, topology, 2 * load.link + 1);
  const Vec3 d = to - from;
  const double length = d.norm();
  LoadResultant r;
  if (const auto* distributed = std::get_if<DistributedLinkLoad>(&load.load)) {
    r.at = from;
    r.wrench.head<3>() = length * (distributed->from + distributed->to) / 2;
    // ∫ (s·d/L) × q(s) ds: the linear load's first moment along the link.
    r.wrench.tail<3>() = d.cross(length * (distributed->from + 2 * distributed->to) / 6);
  } else {
    const auto& point = std::get<PointLinkLoad>(load.load);
    r.at = from + point.position * d;
    r.wrench << point.force, point.moment;
  }
  return r;
}

void add_internal_forces(const Model& model, const Topology& topology, const CaseLoads& loads,
                         Result& result) {
  std::map<int, std::vector<const ResolvedLinkLoad*>> along;
  for (const ResolvedLinkLoad& load : loads.link_loads) along[load.link].push_back(&load);
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const Link& link = model.links[l];
    const auto* beam = std::get_if<BeamLink>(&link.kind);
    LinkResult& r = result.links[l];
    r.internal_forces.clear();
    if (!beam || !r.from.wrench) continue;
    const Vec3& from = end_position(model, topology, 2 * static_cast<int>(l));
    const Vec3& to = end_position(model, topology, 2 * static_cast<int>(l) + 1);
    const Mat3 axes = axes_of(*beam, from, to);
    std::vector<BeamLoad> local;
    std::vector<double> stations;
    for (int k = 0; k < kEvenStations; ++k)
      stations.push_back(static_cast<double>(k) / (kEvenStations - 1));
    if (const auto found = along.find(static_cast<int>(l)); found != along.end())
      for (const ResolvedLinkLoad* load : found->second) {
        local.push_back(local_load(axes, load->load));
        if (const auto* point = std::get_if<PointLinkLoad>(&load->load))
          stations.push_back(point->position);
      }
    std::sort(stations.begin(), stations.end());
    stations.erase(std::unique(stations.begin(), stations.end()), stations.end());
    Vec6 from_end;
    from_end << axes * r.from.wrench->head<3>(), axes * r.from.wrench->tail<3>();
    const double length = (to - from).norm();
    r.internal_forces.reserve(stations.size());
    for (double station : stations)
      r.internal_forces.push_back(
          {station, beam_internal_forces(length, from_end, local, station)});
  }
}

void add_loaded_internal_forces(const Model& model, const Topology& topology,
                                const CaseLoads& loads, Result& result) {
  std::map<int, std::vector<const ResolvedLinkLoad*>> along;
  for (const ResolvedLinkLoad& load : loads.link_loads) along[load.link].push_back(&load);
  // Three Gauss points integrate a linear load over the cubic shape (degree 4) exactly.
  constexpr double kGaussPoints[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  constexpr double kGaussWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    LinkResult& r = result.links[l];
    if (r.internal_forces.empty() || !r.from.wrench || !r.from.deflection || !r.to.deflection)
      continue;
    const int from = 2 * static_cast<int>(l);
    const Vec3& p_from = end_position(model, topology, from);
    const Vec3& p_to = end_position(model, topology, from + 1);
    const LoadedLinkShape shape(model.links[l], p_from, p_to);
    auto state = [](const Vec3& unloaded, const Vec6& deflection) {
      EndState s;
      s.position = unloaded + deflection.head<3>();
      s.rotation = rotation_matrix(deflection.tail<3>());
      return s;
    };
    const EndState i = state(p_from, *r.from.deflection), j = state(p_to, *r.to.deflection);
    const Mat3 axes = shape.axes(i, j);
    const double length = shape.length();
    std::vector<const ResolvedLinkLoad*> none;
    const auto found = along.find(static_cast<int>(l));
    const auto& on_link = found == along.end() ? none : found->second;
    for (InternalForces& at : r.internal_forces) {
      const double station = at.position;
      const Vec3 cut = shape.point(i, j, station);
      Vec3 force = r.from.wrench->head<3>();
      Vec3 moment = r.from.wrench->tail<3>() + (i.position - cut).cross(force);
      for (const ResolvedLinkLoad* load : on_link) {
        if (const auto* q = std::get_if<DistributedLinkLoad>(&load->load)) {
          for (int g = 0; g < 3; ++g) {
            const double s = station * (1 + kGaussPoints[g]) / 2;
            const double weight = kGaussWeights[g] * station / 2 * length;
            const Vec3 per_length = q->from + s * (q->to - q->from);
            force += weight * per_length;
            moment += weight * (shape.point(i, j, s) - cut).cross(per_length);
          }
        } else {
          const auto& point = std::get<PointLinkLoad>(load->load);
          if (point.position < station) {
            force += point.force;
            moment += point.moment + (shape.point(i, j, point.position) - cut).cross(point.force);
          }
        }
      }
      at.forces << -(axes * force), -(axes * moment);
    }
  }
}

}  // namespace stiffmsa::detail
