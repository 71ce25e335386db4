"""stiffmsa: the Cartesian stiffness of robot manipulators by extended matrix structural analysis.

Read a model file or build a model in code, solve it, and read the compliance and stiffness of
its end effectors as numpy arrays::

    import stiffmsa
    model = stiffmsa.load_model("examples/planar-2r.yaml")
    result = stiffmsa.solve(model)
    K = result.end_effectors["tool"].stiffness      # (6, 6) float64, or None

Sweep a parametric model over a grid of poses, in C++ threads::

    family = stiffmsa.load_family("examples/planar-3rpr-parametric.yaml")
    rows = family.sweep(grid={"x": (-0.1, 0.1, 41), "y": (-0.1, 0.1, 41)})
    rows.columns["platform.k_trans_min"]             # one float64 per pose

The whole API is described in docs/python.md.
"""

from __future__ import annotations

import os
from typing import Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

from . import _core
from ._core import (
    AnalysisInfo,
    AnalysisMode,
    Connection,
    CriticalLoad,
    DistributedLinkLoad,
    EndEffectorResult,
    InternalForces,
    JointResult,
    Kinematics,
    LinkEndResult,
    LinkLoad,
    LinkResult,
    Load,
    LoadCase,
    Material,
    Model,
    ModelFamily,
    Parameter,
    PointLinkLoad,
    PrincipalStiffness,
    Result,
    Section,
    SolveOptions,
    SolveReport,
    SupportResult,
    SweepResult,
    SystemSize,
    check,
    principal_stiffness,
)
from .errors import (Diagnostic, Error, InputError, IoError, NameError, NoEquilibriumError,
                     SingularModelError, UsageError)

__all__ = [
    "AnalysisInfo", "AnalysisMode", "Connection", "CriticalLoad", "Diagnostic", "DistributedLinkLoad",
    "EndEffectorResult", "Error", "InputError", "InternalForces", "IoError", "JointResult", "Kinematics",
    "LinkEndResult", "LinkLoad", "LinkResult", "Load", "LoadCase", "Material", "Model", "ModelFamily",
    "NoEquilibriumError", "Parameter", "PointLinkLoad", "PrincipalStiffness", "Result", "Section",
    "SingularModelError",
    "SolveOptions", "SolveReport", "SupportResult", "SweepResult", "SystemSize", "UsageError", "check",
    "load_family", "load_model", "principal_stiffness", "solve",
]

__version__: str = _core.__version__

PathLike = Union[str, "os.PathLike[str]"]

_DEFAULTS = SolveOptions()


def _options(solver: str, accept_idle_motions: bool, singular_rcond: float, max_relative_residual: float,
             refinement_steps: int, warn_condition: float, mode: Union[None, str, AnalysisMode] = None,
             critical_load: Optional[bool] = None) -> SolveOptions:
    return SolveOptions(solver=solver, accept_idle_motions=accept_idle_motions, singular_rcond=singular_rcond,
                        max_relative_residual=max_relative_residual, refinement_steps=refinement_steps,
                        warn_condition=warn_condition, mode=mode, critical_load=critical_load)


def _values(values: Optional[Mapping[str, float]], parameters: Mapping[str, float]) -> Dict[str, float]:
    merged = dict(values or {})
    merged.update(parameters)
    return {str(name): float(value) for name, value in merged.items()}


def load_model(path: PathLike, **values: float) -> Model:
    """Read and validate a model file (YAML or JSON).

    Keyword arguments replace parameters' defaults of a parametric model, as
    ``stiffmsa solve MODEL --set name=value`` does: ``load_model("arm.yaml", x=0.1)``.

    Raises :class:`InputError` listing every defect (with file, line, column and key), or
    :class:`IoError` when the file cannot be read, or :class:`NameError` (a :class:`UsageError`)
    for a value that names no parameter.
    """
    return _core.load_model(os.fspath(path), _values(None, values))


def solve(model: Model, solver: str = "auto", accept_idle_motions: bool = False, *,
          singular_rcond: float = _DEFAULTS.singular_rcond,
          max_relative_residual: float = _DEFAULTS.max_relative_residual,
          refinement_steps: int = _DEFAULTS.refinement_steps,
          warn_condition: float = _DEFAULTS.warn_condition,
          mode: Union[None, str, AnalysisMode] = None, critical_load: Optional[bool] = None) -> Result:
    """Solve a model: the compliance, stiffness and deflection of every end effector, the link
    ends' deflections and wrenches, the joints' relative deflections and wrenches and the
    supports' reactions (a :class:`Result`, the content of ``stiffmsa solve --json``).

    ``solver``: ``"auto"`` (tree-shaped models and parallel robots without factorising, frames
    by their condensed stiffness, others by a sparse LU), or a sparse LU: ``"sparse_lu"``,
    ``"umfpack"``, ``"klu"``. ``accept_idle_motions``: solve despite free motions that move no
    end effector (the spin of a leg about its own axis). The other options are the C++
    ``SolveOptions``': the reciprocal condition below which the system is singular, the largest
    relative residual accepted, the iterative refinement steps, and the condition above which a
    warning is given. ``mode``: ``"linear"`` or ``"loaded"`` (an :class:`AnalysisMode` too), or
    ``None`` for the model's own (``Model.mode``). ``critical_load``: whether to find every load
    case's critical load factor (``Result.critical_load``): ``None`` where the result's contract
    has it (the loaded mode, load cases, loads along links, gravity or settlements), ``True``
    always, ``False`` never (it saves the factor's cost; every other number is the same); another
    type raises ``TypeError``.

    Raises :class:`InputError` for an invalid model, :class:`SingularModelError` for a
    mechanism (its ``details`` name the free motions) and, in the loaded mode,
    :class:`NoEquilibriumError` where the load path passes a critical point or no equilibrium is
    found (its ``load_factor`` says how far it got).
    """
    return _core._solve(model, _options(solver, accept_idle_motions, singular_rcond, max_relative_residual,
                                        refinement_steps, warn_condition, mode, critical_load))


def load_family(path: PathLike, **values: float) -> ModelFamily:
    """Read a parametric model file (its ``parameters:``) as a :class:`ModelFamily`.

    Keyword arguments replace parameters' defaults, as ``--set`` does; the parameters a sweep
    does not vary keep them. A file without parameters is a family of one model.
    """
    return _core._load_family(os.fspath(path), _values(None, values))


# ---- ModelFamily's methods, here for their Python signatures -----------------------------

def _from_function(function: Callable[..., Model], parameters: Mapping[str, float], *,
                   units: Optional[Mapping[str, str]] = None, name: Optional[str] = None) -> ModelFamily:
    """A family whose members ``function(**values)`` builds and returns as a :class:`Model`.

    ``parameters`` gives each parameter's default, in order: ``{"x": 0.0, "y": 0.1}``; ``units``
    their units for labels. Slower than a model file's family: every pose calls Python and holds
    the GIL, so a sweep's threads take turns. An exception raised by the function makes the pose
    ``invalid`` in a sweep (its message says what was raised) and is raised as it is by
    ``build`` and ``solve``.
    """
    names = [str(p) for p in parameters]
    units = units or {}
    unknown = set(units) - set(names)
    if unknown:
        raise UsageError(f"units given for {sorted(unknown)}, which are not parameters")
    return ModelFamily._from_function(function, names, [float(parameters[p]) for p in names],
                                      [str(units.get(p, "")) for p in names],
                                      name if name is not None else getattr(function, "__name__", "family"))


def _build(self: ModelFamily, values: Optional[Mapping[str, float]] = None, /, **parameters: float) -> Model:
    """The member at the defaults, with the given parameters replaced: ``family.build(x=0.1)``
    (or ``family.build({"x": 0.1})``)."""
    return self._build(_values(values, parameters))


def _family_solve(self: ModelFamily, values: Optional[Mapping[str, float]] = None, /, *, solver: str = "auto",
                  accept_idle_motions: bool = False, singular_rcond: float = _DEFAULTS.singular_rcond,
                  max_relative_residual: float = _DEFAULTS.max_relative_residual,
                  refinement_steps: int = _DEFAULTS.refinement_steps,
                  warn_condition: float = _DEFAULTS.warn_condition, mode: Union[None, str, AnalysisMode] = None,
                  critical_load: Optional[bool] = None, **parameters: float) -> Result:
    """Solve one member: ``family.solve(x=0.1, y=0.0)`` is ``solve(family.build(x=0.1, y=0.0))``.

    The options are :func:`solve`'s; a parameter named like an option is given in the mapping
    ``values`` instead: ``family.solve({"solver": 2.0})``.
    """
    return self._solve(_values(values, parameters),
                       _options(solver, accept_idle_motions, singular_rcond, max_relative_residual,
                                refinement_steps, warn_condition, mode, critical_load))


def _with_defaults(self: ModelFamily, **values: float) -> ModelFamily:
    """The same family with other defaults for the given parameters."""
    return self._with_defaults(_values(None, values))


def _sweep(self: ModelFamily, grid: Optional[Mapping[str, Tuple[float, float, int]]] = None,
           poses: Optional[Mapping[str, Sequence[float]]] = None, *, threads: Optional[int] = None,
           full: bool = False, progress: Optional[Callable[[int, int], object]] = None, solver: str = "auto",
           accept_idle_motions: bool = False, singular_rcond: float = _DEFAULTS.singular_rcond,
           max_relative_residual: float = _DEFAULTS.max_relative_residual,
           refinement_steps: int = _DEFAULTS.refinement_steps,
           warn_condition: float = _DEFAULTS.warn_condition,
           mode: Union[None, str, AnalysisMode] = None) -> SweepResult:
    """Solve the family at many poses, as ``stiffmsa sweep`` does, and return its rows.

    Give the poses either as ``grid={"x": (start, stop, count), "y": (...)}`` (every
    combination, both ends included, the first parameter varying fastest) or as
    ``poses={"x": array, "y": array}`` (one value per pose for each swept parameter; a pandas
    DataFrame works too). Parameters not swept keep their defaults.

    ``threads``: how many threads solve poses (``None``: every core); they run in C++ with the
    GIL released. ``full``: also the 36 compliance and 36 stiffness entries per end effector
    (columns ``E.C11`` ... ``E.K66``). ``progress(done, total)`` is called now and then, never
    from two threads at once. The solve options are :func:`solve`'s.

    A pose that fails gets a status (``singular``, ``free-motion``, ``invalid``, ``inaccurate``,
    ``error``) and a message; the sweep goes on. Raises :class:`InputError` when the defaults
    give an invalid model and :class:`NameError` (a :class:`UsageError`) when a swept name is not
    a parameter.
    """
    options = _options(solver, accept_idle_motions, singular_rcond, max_relative_residual, refinement_steps,
                       warn_condition, mode)
    return self._sweep(grid, poses, options, full, threads, progress)


ModelFamily.from_function = staticmethod(_from_function)
ModelFamily.build = _build
ModelFamily.solve = _family_solve
ModelFamily.with_defaults = _with_defaults
ModelFamily.sweep = _sweep


def _to_pandas(self: SweepResult):
    """The rows as a pandas DataFrame, one column per CSV column (needs pandas)."""
    try:
        import pandas
    except ImportError as error:
        raise ImportError("SweepResult.to_pandas() needs pandas (Debian: python3-pandas)") from error
    return pandas.DataFrame(self.columns)


SweepResult.to_pandas = _to_pandas
