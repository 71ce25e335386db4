"""The exceptions stiffmsa raises: every one is a :class:`stiffmsa.Error`."""

from __future__ import annotations

from typing import List, Optional, Sequence

# NameError is stiffmsa.errors.NameError (and stiffmsa.NameError), left out of the star-import so
# that it does not hide Python's own NameError.
__all__ = ["Error", "InputError", "SingularModelError", "NoEquilibriumError", "IoError", "UsageError",
           "Diagnostic"]


class Error(Exception):
    """Base class of every stiffmsa error."""


class Diagnostic:
    """One defect of a model: where it is (``file``, ``line``, ``column``; ``None`` where not
    known, as for a model built in code), which key (``key_path``, e.g. ``"joints.J3.axis"``) and
    what is wrong (``message``). ``str()`` gives ``file:line:column: key_path: message``."""

    __slots__ = ("file", "line", "column", "key_path", "message", "_text")

    def __init__(self, file: Optional[str], line: Optional[int], column: Optional[int],
                 key_path: str, message: str, text: Optional[str] = None) -> None:
        self.file = file
        self.line = line
        self.column = column
        self.key_path = key_path
        self.message = message
        self._text = text

    def __str__(self) -> str:
        if self._text is not None:
            return self._text
        where = ":".join(str(part) for part in (self.file, self.line, self.column) if part is not None)
        return "".join(part + ": " for part in (where, self.key_path) if part) + self.message

    def __repr__(self) -> str:
        return (f"Diagnostic(file={self.file!r}, line={self.line!r}, column={self.column!r}, "
                f"key_path={self.key_path!r}, message={self.message!r})")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Diagnostic):
            return NotImplemented
        return all(getattr(self, name) == getattr(other, name)
                   for name in ("file", "line", "column", "key_path", "message"))


class InputError(Error):
    """The model (a file or a model built in code) is invalid. ``diagnostics`` lists every
    defect found, each a :class:`Diagnostic`."""

    def __init__(self, message: str, diagnostics: Sequence[Diagnostic] = ()) -> None:
        super().__init__(message)
        self.diagnostics: List[Diagnostic] = list(diagnostics)


class SingularModelError(Error):
    """The model is valid but cannot be solved. ``cause`` is ``"free_motion"`` (a mechanism;
    ``details`` names the free motions as the ``stiffmsa`` command does) or ``"numerical"``
    (singular to working precision)."""

    def __init__(self, message: str, cause: str = "numerical", details: Sequence[str] = ()) -> None:
        self.summary = message
        self.cause = cause
        self.details: List[str] = list(details)
        super().__init__("\n  ".join([message, *self.details]))


class NoEquilibriumError(Error):
    """The loaded mode found no equilibrium under the full loads: the load path passed a limit
    point or a bifurcation (the structure buckles or snaps), or Newton's iterations did not
    converge however small the load step. ``load_factor`` is the last load factor reached in
    equilibrium (a fraction of the loads)."""

    def __init__(self, message: str, load_factor: float = 0.0) -> None:
        super().__init__(message)
        self.load_factor = load_factor


class IoError(Error, OSError):
    """A file could not be read or written (not a defect of the model's content)."""


class UsageError(Error, ValueError):
    """A call's arguments are invalid: an unknown solver or parameter, a wrong shape, a value
    out of range."""


class NameError(UsageError, LookupError):
    """A name looked up through the API that is not there: a result's end effector, link, joint,
    support or load case, a model's material or section, a family's parameter. ``kind`` says what
    it was to be (``"end effector"``, ``"parameter"``), ``name`` is the name asked for, and
    ``suggestion`` the nearest name there is when one is near enough to be a typo (else
    ``None``). A :class:`UsageError` too, and a ``LookupError``; ``from stiffmsa import *`` leaves
    it out, so that it does not hide Python's own ``NameError``."""

    def __init__(self, message: str, kind: str = "", name: str = "",
                 suggestion: Optional[str] = None) -> None:
        super().__init__(message)
        self.kind = kind
        self.name = name
        self.suggestion = suggestion
