"""Factory of compiled step loops: one variant per combination of effects a scene calls for.

:func:`make_advance` writes a copy of ``_advance_template.py`` whose VARIANT block holds the
scene's constants (``HAS_FRICTION = False`` ...) into x3dpd's kernel cache and imports it. Numba
treats module globals as compile-time constants, so an absent effect is a constant-false branch
that LLVM deletes: no per-step test, no cost. Because every variant is a real file, numba's
on-disk cache works for it; the cache folder's name includes a hash of all x3dpd sources and the
numba version, so editing any kernel can never reuse stale machine code.

The cache lives in ``$X3DPD_CACHE_DIR`` or ``~/.cache/x3dpd``. Variants that call a user USRFRC
function are compiled in memory and not cached (the user file may change at any time).
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
from dataclasses import dataclass
from pathlib import Path

import numba

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


def make_advance(variant: Variant, user_force=None):
    """The module implementing ``variant`` (its ``advance`` and ``_forces`` kernels).

    ``user_force``: a numba-compiled ``usrfrc(time, coords, vels, force)`` (variant.user_force).
    """
    key = (variant, id(user_force) if user_force is not None else None)
    if key in _LOADED:
        return _LOADED[key]
    source = variant_source(variant)
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    stem = variant.name() + (f"_user{len(_LOADED)}_{os.getpid()}" if variant.user_force else "")
    path = folder / f"{stem}.py"
    if not path.exists() or path.read_text() != source:
        tmp = path.with_suffix(f".tmp{os.getpid()}")
        tmp.write_text(source)
        os.replace(tmp, path)
    mod_name = f"x3dpd_kernels_{_source_hash()}_{stem}"
    spec = importlib.util.spec_from_file_location(mod_name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[mod_name] = module
    spec.loader.exec_module(module)
    if variant.user_force:
        module.USER_FORCE = user_force
        _disable_cache(module)
    _LOADED[key] = module
    return module


def _disable_cache(module) -> None:
    """Variants with a user force compile in memory only (the user file may change)."""
    for name in ("advance", "_forces"):
        disp = getattr(module, name)
        disp._cache = numba.core.caching.NullCache()
