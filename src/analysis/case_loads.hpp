#pragma once
// The load cases of a solve as the equations take them (docs/theory.md §12, §13): each case's
// wrenches at the link ends, loads along links replaced by their equivalent end loads, and what
// turns the solution back into the true end wrenches and the internal forces of loaded beams.
#include <map>
#include <string>
#include <vector>

#include "assembly/topology.hpp"
#include "elements/beam_loads.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa::detail {

// A load along a link or a self-weight, resolved: the link and its load in global axes.
struct ResolvedLinkLoad {
  int link = -1;
  std::variant<DistributedLinkLoad, PointLinkLoad> load;
};

struct CaseLoads {
  std::string name;  // "" for the unnamed case
  // Whether the case carries the preloads and settlements: every load case does; the robot's
  // self-weight column (deflection_gravity) carries its weight alone.
  bool with_state = true;
  // Per link end: the loads applied there plus the equivalent end loads of the loads along its
  // link (the negated fixed-end wrenches), global, moments about the end's point.
  std::vector<Vec6> external;
  // Per link end, where the case has loads along links (else empty): the loads applied there
  // alone, and the wrench a clamp would exert on the link there under its loads along it
  // (global; the true end wrench is the solved one plus it).
  std::vector<Vec6> end_loads;
  std::vector<Vec6> fixed_end;
  // Every load along a link, self-weight included, in global axes.
  std::vector<ResolvedLinkLoad> link_loads;
  bool loaded = false;  // any non-zero load
  const std::vector<Vec6>& applied_at_ends() const {
    return end_loads.empty() ? external : end_loads;
  }
};

// Whether the model's own loads, link loads and gravity form a case of their own: they do where
// any is given or where the model names no case (model.hpp, Model::load_cases).
bool has_unnamed_case(const Model& model);

// Whether any case loads a link along its length (a link load, or gravity on a beam whose
// material has a density): the results then give the beams' internal forces.
bool loads_along_links(const Model& model);

// The unnamed case (where there is one), then each named case, then, where the model has
// self-weight loads (Load::self_weight), those alone without preloads or settlements.
// Throws InputError for a point load's position outside [0, 1] and a settlement along a free
// direction.
std::vector<CaseLoads> case_loads(const Model& model, const Topology& topology);

// A load along a link as one wrench about a point of the link (its `from` end for a distributed
// load, a point load's own place), for the equilibrium check.
struct LoadResultant {
  Vec3 at = Vec3::Zero();
  Vec6 wrench = Vec6::Zero();
};
LoadResultant resultant(const Model& model, const Topology& topology, const ResolvedLinkLoad& load);

// The internal forces of every beam from its solved end wrenches (`result`'s, true ones) and the
// case's loads along it: at 11 evenly spaced stations and at each point load's position.
void add_internal_forces(const Model& model, const Topology& topology, const CaseLoads& loads,
                         Result& result);

// The same in the loaded mode, from `result`'s loaded state (end deflections and true end
// wrenches, docs/theory.md §15.9): at the stations the linear result gave each beam, the wrench
// about the section's point on the beam's current shape that the part beyond exerts on the part
// before, in the beam's co-rotated axes, the loads acting on that shape.
void add_loaded_internal_forces(const Model& model, const Topology& topology,
                                const CaseLoads& loads, Result& result);

}  // namespace stiffmsa::detail
