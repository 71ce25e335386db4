#pragma once
// The analysis's way into a Workspace: its internals are no part of the public API, so that a
// binding wraps Workspace as an opaque handle and the analysis may reshape them freely.
#include "stiffmsa/analysis.hpp"

namespace stiffmsa::detail {

struct WorkspaceAccess {
  static Workspace::Impl& impl(Workspace& workspace) { return *workspace.impl_; }
  // The workspace of a model whose index the caller built and keeps.
  static Workspace of(const Model& model, const ModelIndex& index) {
    return Workspace(model, index);
  }
};

}  // namespace stiffmsa::detail
