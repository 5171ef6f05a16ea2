"""User force files: ``force.py`` defining ``usrfrc(time, coords, vels, force)``, X3D's USRFRC
subroutine as Python that x3dpd compiles with numba (report Appendix C; docs/usrfrc.md).

:func:`load_user_force` imports a file with ``NODE_INDEX`` (X3D's GETIDN) injected, compiles it,
and checks it with a trial call; :func:`build_external_forces` gathers the built-in laws
(x3dpd.physics.usrfrc) and the user files of a run.
"""

from __future__ import annotations

import importlib.util
import inspect
import itertools
import os
import re
import sys
import traceback
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba.core.errors import NumbaError

from x3dpd._jit import kernel
from x3dpd.errors import UsrfrcError
from x3dpd.physics.usrfrc import _node_ids, force_table, split_specs


@dataclass(frozen=True)
class UserForce:
    """A loaded user force file.

    Attributes
    ----------
    path : str
        The file as the user named it.
    function : callable
        ``usrfrc(time, coords, vels, force)``: a numba dispatcher, or the plain Python function
        when ``python`` is True.
    python : bool
        True for the slower fallback: the solver must call ``function`` from Python between
        steps (one step lagged) instead of from the compiled step.
    node_index : (max_id + 1,) int64
        The ``NODE_INDEX`` array injected into the file's module.
    """

    path: str
    function: Callable
    python: bool
    node_index: np.ndarray

    def __call__(self, time, coords, vels, force) -> None:
        self.function(time, coords, vels, force)


def node_index_array(model_or_node_ids) -> np.ndarray:
    """``NODE_INDEX``: int64 array of size ``max_id + 1``; ``NODE_INDEX[id]`` is the node's
    index, -1 where no node has that id (X3D's ``GETIDN``)."""
    ids = _node_ids(model_or_node_ids)
    index = np.full(int(ids[-1]) + 1 if ids.size else 0, -1, dtype=np.int64)
    index[ids] = np.arange(ids.size, dtype=np.int64)
    return index


_module_counter = itertools.count()
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def _where(exc: BaseException, path: str) -> str:
    """``path:line`` of the deepest traceback frame in ``path`` (or just ``path``)."""
    line = getattr(exc, "lineno", None) if isinstance(exc, SyntaxError) else None
    real = os.path.realpath(path)
    for frame in traceback.extract_tb(exc.__traceback__):
        if os.path.realpath(frame.filename) == real:
            line = frame.lineno
    return f"{path}:{line}" if line else path


def _import(path: str, node_index: np.ndarray):
    """Execute ``path`` as a fresh module with ``NODE_INDEX`` injected (before and after)."""
    stem = re.sub(r"\W", "_", os.path.basename(path))
    name = f"x3dpd_usrfrc_{next(_module_counter)}_{stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise UsrfrcError(f"{path}: cannot be imported as a Python file")
    module = importlib.util.module_from_spec(spec)
    module.NODE_INDEX = node_index
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except Exception as exc:  # the user's file can raise anything
        sys.modules.pop(name, None)
        raise UsrfrcError(f"{_where(exc, path)}: importing the user force file failed: "
                          f"{type(exc).__name__}: {exc}") from exc
    module.NODE_INDEX = node_index
    return module


def _usrfrc_function(module, path: str):
    fn = getattr(module, "usrfrc", None)
    fn = getattr(fn, "py_func", fn)  # already decorated with numba.njit: recompile our way
    if fn is None or not inspect.isfunction(fn):
        raise UsrfrcError(f"{path}: defines no function usrfrc(time, coords, vels, force)")
    params = inspect.signature(fn).parameters.values()
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    odd = [p for p in params if p.kind == p.VAR_POSITIONAL or (p.kind == p.KEYWORD_ONLY
                                                              and p.default is p.empty)]
    if len(positional) != 4 or odd:
        found = ", ".join(p.name for p in params)
        raise UsrfrcError(f"{path}:{fn.__code__.co_firstlineno}: usrfrc must take exactly "
                          f"(time, coords, vels, force); found usrfrc({found})")
    return fn


def _jit_helpers(module) -> None:
    """Compile the file's other plain functions lazily so ``usrfrc`` can call them."""
    for name, obj in list(vars(module).items()):
        if inspect.isfunction(obj) and obj.__module__ == module.__name__ and name != "usrfrc":
            setattr(module, name, kernel(cache=False)(obj))


def _numba_message(exc: BaseException, path: str) -> str:
    """``file:line: message`` plus the offending source line, from a numba compile error."""
    lines = [ln.rstrip() for ln in _ANSI.sub("", str(exc)).splitlines()]
    at = next((k for k, ln in enumerate(lines) if re.match(r'\s*File ".+", line \d+:', ln)), None)
    head = lines if at is None else lines[:at]
    message = [ln.strip() for ln in head if ln.strip() and not ln.startswith(("Failed in",
                                                                               "During:"))]
    text = " ".join(message[:3]) or type(exc).__name__
    if at is None:  # numba gives no place for undefined names: find the first use
        name = re.search(r"name '(\w+)' is not defined", text)
        try:
            source = open(path, encoding="utf-8").read().splitlines() if name else []
        except OSError:
            source = []
        for k, ln in enumerate(source, 1):
            if re.search(rf"\b{name[1]}\b", ln.split("#")[0]):
                return f"{path}:{k}: numba cannot compile usrfrc: {text}\n    {ln.strip()}"
        return f"{path}: numba cannot compile usrfrc: {text}"
    m = re.match(r'\s*File "(.+)", line (\d+):', lines[at])
    where = f"{path}:{m[2]}" if os.path.realpath(m[1]) == os.path.realpath(path) else \
        f"{m[1]}:{m[2]}"
    code = ""
    for ln in lines[at + 1:]:
        if ln.strip().startswith("^"):
            break
        if ln.strip():
            code = ln.strip()
    return f"{where}: numba cannot compile usrfrc: {text}" + (f"\n    {code}" if code else "")


def _trial_call(fn, n: int, path: str, coords=None) -> None:
    """Call ``fn`` once at t = 0 on arrays of the right shapes; it may only change ``force``."""
    rng = np.random.default_rng(0)
    x = (np.array(coords, dtype=np.float64, order="C") if coords is not None
         else rng.uniform(-1.0, 1.0, (n, 3)))
    vel = rng.uniform(-1.0, 1.0, (n, 6))
    force = np.zeros((n, 6))
    x_copy, vel_copy = x.copy(), vel.copy()
    fn(0.0, x, vel, force)
    for name, a, b in (("coords", x, x_copy), ("vels", vel, vel_copy)):
        if not np.array_equal(a, b, equal_nan=True):
            raise UsrfrcError(f"{path}: usrfrc modified its {name} argument; it may only ADD "
                              "to force (X3D: DO NOT MODIFY)")


def load_user_force(path, model_or_node_ids, allow_python: bool = False,
                    coords=None) -> UserForce:
    """Import a user force file and compile its ``usrfrc(time, coords, vels, force)``.

    The file is executed as a fresh module with the global ``NODE_INDEX`` (see
    :func:`node_index_array`) injected; ``usrfrc`` (and the file's other plain functions, which
    it may call) are then compiled with numba and called once on arrays of the right shapes to
    check that they compile and leave ``coords`` and ``vels`` untouched.

    Parameters
    ----------
    path : str or path-like
        The user force file.
    model_or_node_ids : Model or (n,) int array
        Ascending user node ids.
    allow_python : bool
        When numba cannot compile the function, return it as plain Python (``python=True``)
        instead of raising (CLI ``--usrfrc-python``).
    coords : (n, 3) array, optional
        Coordinates for the trial call (default: random values in [-1, 1]).

    Raises
    ------
    UsrfrcError
        Missing file, import failure, no ``usrfrc``, wrong signature, compile failure (with the
        file:line and numba's message) or a trial call that fails or modifies coords/vels.
    """
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise UsrfrcError(f"{path}: user force file not found")
    node_index = node_index_array(model_or_node_ids)
    n = int(_node_ids(model_or_node_ids).shape[0])
    module = _import(path, node_index)
    fn = _usrfrc_function(module, path)
    _jit_helpers(module)
    compiled = kernel(cache=False)(fn)
    try:
        _trial_call(compiled, n, path, coords)
        return UserForce(path, compiled, False, node_index)
    except NumbaError as exc:
        message = _numba_message(exc, path)
        if not allow_python:
            raise UsrfrcError(message + "\n(--usrfrc-python runs it as plain Python, slower)") \
                from None
    except UsrfrcError:
        raise
    except Exception as exc:  # noqa: BLE001 -- the user's code raised at run time
        raise UsrfrcError(f"{_where(exc, path)}: usrfrc raised {type(exc).__name__}: {exc} "
                          "in a trial call at t = 0") from exc
    # Fallback: a fresh module whose helpers stay plain Python.
    fn = _usrfrc_function(_import(path, node_index), path)
    try:
        _trial_call(fn, n, path, coords)
    except UsrfrcError:
        raise
    except Exception as exc:  # noqa: BLE001
        raise UsrfrcError(f"{_where(exc, path)}: usrfrc raised {type(exc).__name__}: {exc} "
                          "in a trial call at t = 0") from exc
    return UserForce(path, fn, True, node_index)


@dataclass(frozen=True)
class ExternalForces:
    """All external forces of a run: the built-in table and the loaded user files."""

    table: np.ndarray
    user: tuple[UserForce, ...]

    @property
    def compiled_user(self) -> tuple[UserForce, ...]:
        return tuple(u for u in self.user if not u.python)

    @property
    def python_user(self) -> tuple[UserForce, ...]:
        return tuple(u for u in self.user if u.python)


def build_external_forces(specs, model_or_node_ids, allow_python: bool = False,
                          coords=None) -> ExternalForces:
    """Parse built-in specs and load user files (deck USRFRC records plus ``--usrfrc``)."""
    laws, files = split_specs(specs)
    table = force_table(laws, model_or_node_ids)
    user = tuple(load_user_force(p, model_or_node_ids, allow_python, coords) for p in files)
    return ExternalForces(table, user)
