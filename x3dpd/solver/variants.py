"""Factory of compiled step loops: one variant per combination of effects a scene calls for.

:func:`make_advance` writes a copy of ``_advance_template.py`` whose VARIANT block holds the
scene's constants (``HAS_FRICTION = False`` ...) into x3dpd's kernel cache and imports it. Numba
treats module globals as compile-time constants, so an absent effect is a constant-false branch
that LLVM deletes: no per-step test, no cost. Because every variant is a real file, numba's
on-disk cache works for it; the cache folder's name includes a hash of all x3dpd sources and the
numba version, so editing any kernel can never reuse stale machine code.

The cache lives in ``$X3DPD_CACHE_DIR`` or ``~/.cache/x3dpd``. A variant that calls user USRFRC
files imports content-hashed copies of them from the same folder (:func:`_user_modules`), so it
is cached too: a second run of an unchanged user file with the same deck starts in about a
second instead of compiling for half a minute; an edited file gets new copies.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np

from x3dpd.physics.coulomb import FRICTION_LAWS

_TEMPLATE = Path(__file__).with_name("_advance_template.py")
_BEGIN = "# --- VARIANT BEGIN ---"
_END = "# --- VARIANT END ---"
_FORCES_BEGIN = "# --- FORCES BEGIN ---\n"
_FORCES_END = "    # --- FORCES END ---"
_FORCES_HERE = "# @FORCES@"
_LOADED: dict[tuple, object] = {}


@dataclass(frozen=True)
class Variant:
    """The compile-time constants of one step loop."""

    gravity: bool = False
    springs: bool = False
    rigid: bool = False
    rigid_rotation: bool = False
    walls: bool = False
    pairs: bool = False
    friction: bool = False
    viscoelastic: bool = False
    external: bool = False
    user_force: bool = False
    python_force: bool = False
    motion: bool = False
    n_maxwell: int = 0
    friction_law: str = "regularized"
    walls_translate: bool = False

    @classmethod
    def from_effects(cls, effects, n_maxwell: int, friction_law: str = "regularized",
                     user_force: bool = False, python_force: bool = False,
                     walls_translate: bool = False) -> "Variant":
        e = set(effects)
        return cls(
            gravity="gravity" in e,
            springs=bool({"springs", "dampers"} & e),
            rigid="rigid_links" in e,
            rigid_rotation="rigid_rotation" in e,
            walls="wall_contact" in e,
            pairs="pair_contact" in e,
            friction="friction" in e,
            viscoelastic="viscoelastic" in e and n_maxwell > 0,
            external="external_force" in e or user_force or python_force,
            user_force=user_force,
            python_force=python_force,
            motion="prescribed_motion" in e,
            n_maxwell=n_maxwell if "viscoelastic" in e else 0,
            friction_law=friction_law,
            walls_translate=walls_translate and "wall_contact" in e,
        )

    def header(self) -> str:
        law = FRICTION_LAWS
        if self.friction_law not in law:
            raise ValueError(f"unknown friction law {self.friction_law!r}; "
                             f"use one of {sorted(law)}")
        lines = [
            f"HAS_GRAVITY = {self.gravity}",
            f"HAS_SPRINGS = {self.springs}",
            f"HAS_RIGID = {self.rigid}",
            f"HAS_RIGID_ROT = {self.rigid_rotation}",
            f"HAS_WALLS = {self.walls}",
            f"HAS_PAIRS = {self.pairs}",
            f"HAS_FRICTION = {self.friction}",
            f"HAS_VISCO = {self.viscoelastic}",
            f"HAS_EXT = {self.external}",
            f"HAS_USER_FORCE = {self.user_force}",
            f"HAS_PY_FORCE = {self.python_force}",
            f"HAS_MOTION = {self.motion}",
            f"N_MAXWELL = {max(self.n_maxwell, 1)}",
            f"WALLS_TRANSLATE = {self.walls_translate}",
            f"from x3dpd.physics.coulomb import {law[self.friction_law]} as FRICTION_LAW",
            "USER_FORCE = None",
        ]
        return "\n".join(lines)

    def name(self) -> str:
        flags = "".join("1" if getattr(self, f) else "0" for f in (
            "gravity", "springs", "rigid", "rigid_rotation", "walls", "pairs", "friction",
            "viscoelastic", "external", "user_force", "python_force", "motion",
            "walls_translate"))
        return f"advance_{flags}_m{self.n_maxwell}_{self.friction_law}"


#: The sources a compiled step loop is made of (its cache key): the template, the laws and
#: helpers it calls, and the compile flags. Editing any other file keeps the cache.
_KERNEL_SOURCES = ("_jit.py", "solver/_advance_template.py", "solver/variants.py",
                   "solver/contact_lists.py", "geometry/faces.py",
                   "physics/*.py", "geometry/cells.py")


def _source_hash() -> str:
    """Hash of the kernel sources and the numba version (the cache folder's name)."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(numba.__version__.encode())
    paths = sorted({p for pattern in _KERNEL_SOURCES for p in root.glob(pattern)})
    for path in paths:
        h.update(path.relative_to(root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def cache_dir() -> Path:
    """Folder of generated variants (``$X3DPD_CACHE_DIR`` or ``~/.cache/x3dpd``)."""
    base = os.environ.get("X3DPD_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "x3dpd")
    return Path(base) / "kernels" / _source_hash()


def variant_source(variant: Variant) -> str:
    """Source text of the module for ``variant``.

    Besides the VARIANT constants, the body of ``_forces`` (between the FORCES markers) is
    copied into ``advance`` at its ``# @FORCES@`` line, re-indented: numba cannot inline a
    function of that many arguments, and calling it every step costs more than small scenes'
    physics (every array argument's reference count is touched).
    """
    text = _TEMPLATE.read_text()
    head, rest = text.split(_BEGIN, 1)
    _, tail = rest.split(_END, 1)
    text = f"{head}{_BEGIN}\n{variant.header()}\n{_END}{tail}"
    body = text.split(_FORCES_BEGIN, 1)[1].split(_FORCES_END, 1)[0]
    lines = text.splitlines(keepends=True)
    out = []
    for line in lines:
        if line.strip().startswith(_FORCES_HERE):
            indent = line[: len(line) - len(line.lstrip())]
            out.extend(indent + b[4:] if b.strip() else b for b in body.splitlines(keepends=True))
        else:
            out.append(line)
    return "".join(out)


def make_advance(variant: Variant, user_files=()):
    """The module implementing ``variant`` (its ``advance`` and ``_forces`` kernels).

    ``user_files``: ``(path, NODE_INDEX)`` of each compiled user force file, called in order
    from the step (variant.user_force). Each becomes a cached copy, see :func:`_user_modules`.
    """
    user_files = tuple((os.fspath(p), np.ascontiguousarray(ix, np.int64)) for p, ix in user_files)
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    users = _user_modules(folder, user_files) if variant.user_force else ()
    key = (variant, users)
    if key in _LOADED:
        return _LOADED[key]
    source = variant_source(variant)
    stem = variant.name()
    if users:
        source = source.replace("\nUSER_FORCE = None\n", "\n" + _user_force_source(users) + "\n", 1)
        stem += "_" + hashlib.sha256(" ".join(users).encode()).hexdigest()[:12]
    path = folder / f"{stem}.py"
    _write_if_changed(path, source)
    module = _import_file(f"x3dpd_kernels_{_source_hash()}_{stem}", path)
    _LOADED[key] = module
    return module


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        tmp = path.with_suffix(f".tmp{os.getpid()}")
        tmp.write_text(text)
        os.replace(tmp, path)


def _import_file(name: str, path: Path):
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


#: Appended to a user force file's cached copy: compile its functions through x3dpd._jit (with
#: numba's disk cache), re-wrapping any the user had decorated with numba themselves.
_USER_FOOTER = """
# ---- added by x3dpd: the node index (again: the file may set a placeholder), and this file's
# functions compiled with numba's disk cache ----
NODE_INDEX = _x3dpd_np.load(__file__[:-3] + ".npy")
import inspect as _x3dpd_inspect  # noqa: E402
from x3dpd._jit import kernel as _x3dpd_kernel  # noqa: E402
for _x3dpd_name, _x3dpd_obj in list(globals().items()):
    _x3dpd_obj = getattr(_x3dpd_obj, "py_func", _x3dpd_obj)
    if _x3dpd_inspect.isfunction(_x3dpd_obj) and _x3dpd_obj.__module__ == __name__:
        globals()[_x3dpd_name] = _x3dpd_kernel(_x3dpd_obj)
"""


def _user_modules(folder: Path, user_files) -> tuple[str, ...]:
    """Import a cached copy of each user force file; return the copies' module names.

    A copy is the user's source with ``NODE_INDEX`` loaded on its first line and again at its
    end (numba freezes a global array into the machine code, so the node numbering is part of
    what is compiled), and the functions compiled through x3dpd._jit (:data:`_USER_FOOTER`).
    Its name is a hash of the file's bytes and the node index: an edited file or another deck
    gets a new copy, an unchanged one reuses its compiled code. The user's code has been
    validated (and compiled once, uncached) by ``load_user_force``.
    """
    names = []
    for path, node_index in user_files:
        text = Path(path).read_text()
        digest = hashlib.sha256(text.encode() + node_index.tobytes()).hexdigest()[:16]
        stem = f"usrfrc_{digest}"
        npy = folder / f"{stem}.npy"
        if not npy.exists():   # its name is its content's hash: an existing one is right
            tmp = folder / f"{stem}.npy.tmp{os.getpid()}"
            with open(tmp, "wb") as f:
                np.save(f, node_index)
            os.replace(tmp, npy)   # atomic: a concurrent run never reads half a file
        head = ("import numpy as _x3dpd_np; NODE_INDEX = _x3dpd_np.load(__file__[:-3] + '.npy')"
                f"  # added by x3dpd: a copy of {path}\n")
        _write_if_changed(folder / f"{stem}.py", head + text + _USER_FOOTER)
        name = f"x3dpd_user_{_source_hash()}_{stem}"
        _import_file(name, folder / f"{stem}.py")
        names.append(name)
    return tuple(names)


def _user_force_source(modules: tuple[str, ...]) -> str:
    """``USER_FORCE``: the user forces' ``usrfrc`` functions, called one after another."""
    lines = [f"from {m} import usrfrc as _user_force_{k}  # noqa: E402"
             for k, m in enumerate(modules)]
    if len(modules) == 1:
        return "\n".join(lines + ["USER_FORCE = _user_force_0"])
    calls = "".join(f"    _user_force_{k}(t, x, vel, force)\n" for k in range(len(modules)))
    return "\n".join(lines + ["from x3dpd._jit import kernel as _user_kernel  # noqa: E402",
                               "", "", "@_user_kernel", "def USER_FORCE(t, x, vel, force):",
                               calls.rstrip("\n"), ""])
