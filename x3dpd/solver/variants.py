# Over 400 lines: effect flags, the template's copy and the cache key belong together.
"""Factory of compiled step loops: one variant per combination of effects a scene calls for.

:func:`make_advance` writes the step-loop template (``_advance_template.py`` and its parts
``_template_*.py``) into x3dpd's kernel cache, with the scene's constants (``HAS_FRICTION =
False`` ...) in its copy of ``_template_variant.py``, and imports it. Numba treats module
globals as compile-time constants, so an absent effect is a constant-false branch that LLVM
deletes: no per-step test, no cost. Because every variant is a set of real files, numba's
on-disk cache works for it; the cache folder's name includes a hash of every source the kernels
are built from (:func:`kernel_sources`) and the numba version, so editing any kernel can never
reuse stale machine code.

The cache lives in ``$X3DPD_CACHE_DIR`` or ``~/.cache/x3dpd``. A variant that calls user USRFRC
files imports content-hashed copies of them from the same folder (:func:`_user_modules`), so it
is cached too: a second run of an unchanged user file with the same deck starts in about a
second instead of compiling for half a minute; an edited file gets new copies.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import os
import re
import sys
from dataclasses import dataclass, field, fields, make_dataclass
from pathlib import Path

import numba
import numpy as np

from x3dpd.geometry.shapes import BY_SHAPE_NAME, SHAPES, kind_of
from x3dpd.physics.effect_units import UNITS
from x3dpd.physics.normal_laws import NORMAL_LAW_API, NORMAL_LAWS
from x3dpd.physics.rolling import ROLLING_LAWS
from x3dpd.physics.tangential_laws import TANGENTIAL_LAW_API, TANGENTIAL_LAWS
from x3dpd.solver.unit_slots import units_source

_TEMPLATE = Path(__file__).with_name("_advance_template.py")
#: The template's parts besides the loop, in import order (``_template_<part>.py``): each is
#: generated per variant beside it, ``variant`` holding the variant's constants.
PARTS = ("variant", "contact", "wall_columns", "walls", "pairs", "pair_passes", "energy")
_PART_MODULE = "x3dpd.solver._template_"
_BEGIN = "# --- VARIANT BEGIN ---"
_END = "# --- VARIANT END ---"
_LOADED: dict[tuple, object] = {}
#: generated loop module name -> (its Variant, its file stem), of every loop made here
_VARIANT_OF: dict[str, tuple] = {}


@dataclass(frozen=True)
class Variant:
    """The compile-time constants of one step loop."""

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
    #: prescribed motions of node DOFs (``--motion``, the effect unit x3dpd.physics.motion)
    motion: bool = False
    n_maxwell: int = 0
    friction_law: str = "regularized"
    #: the rolling-resistance law (x3dpd.physics.rolling; FRICTION card), "none" compiles none
    rolling_law: str = "none"
    walls_translate: bool = False
    normal_law: str = "lee_radok"
    #: the analytic wall shapes of the scene, by name in registry order ("cylinder",
    #: "cylinder+capsule"; x3dpd.geometry.shapes), "" for none
    shapes: str = ""
    #: every particle has the same radius, kind and law constants: the pair response reads
    #: them once instead of gathering them per contact
    one_particle_kind: bool = False
    #: every particle meets the triangulated walls with the same constants (radius, the wall
    #: laws', friction): their contacts go through columns and a vectorized response
    #: (``_template_wall_columns``), else one at a time (``_template_walls``)
    one_wall_kind: bool = False
    #: a structure given by its modes (MODAL card, x3dpd.physics.modal)
    modal: bool = False
    #: MATID type 2 elements: spring-dampers along the line between two nodes
    axial_springs: bool = False
    #: MATID type 3 elements: rotational spring-dampers (each integrates its own rotation)
    rotational_springs: bool = False
    #: the pair contacts' filter and response run in chunks on numba's threads (the run option
    #: ``threads`` > 1; ``_template_pair_passes``): a loop of its own, so that single-thread
    #: runs compile none of numba's parallel code
    threaded: bool = False

    @classmethod
    def from_effects(cls, effects, n_maxwell: int, friction_law: str = "regularized",
                     user_force: bool = False, python_force: bool = False,
                     walls_translate: bool = False, normal_law: str = "lee_radok",
                     one_particle_kind: bool = False, rolling_law: str = "none",
                     threaded: bool = False, one_wall_kind: bool = False) -> "Variant":
        e = set(effects)
        return cls(
            rigid_rotation="rigid_rotation" in e,
            walls="wall_contact" in e,
            pairs="pair_contact" in e,
            friction="friction" in e,
            viscoelastic="viscoelastic" in e and n_maxwell > 0,
            user_force=user_force,
            python_force=python_force,
            n_maxwell=n_maxwell if "viscoelastic" in e else 0,
            friction_law=friction_law,
            rolling_law=rolling_law if {"wall_contact", "pair_contact"} & e else "none",
            walls_translate=walls_translate and "wall_contact" in e,
            normal_law=normal_law,
            shapes="+".join(s.name for s in SHAPES if s.effect in e),
            one_particle_kind=one_particle_kind and "pair_contact" in e,
            one_wall_kind=one_wall_kind and "wall_contact" in e,
            threaded=threaded and "pair_contact" in e,
            # an effect unit is compiled when the scene has any of its effects
            **{u.flag: bool(set(u.effects) & e) for u in UNITS if not u.runtime},
        )

    def header(self) -> str:
        """The VARIANT block of the generated module, one constant per field: a flag ``f``
        becomes ``HAS_F``, a count ``n`` becomes ``N``, a law its function imported as ``LAW``."""
        lines = []
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "shapes":
                lines.append(_shapes_source(value))
            elif f.name in _LAWS:
                registry, imports = _LAWS[f.name]
                if value not in registry:
                    raise ValueError(f"unknown {f.name.replace('_', ' ')} {value!r}; "
                                     f"use one of {sorted(registry)}")
                lines.append(imports(value))
            elif isinstance(value, bool):
                lines.append(f"HAS_{f.name.upper()} = {value}")
            else:
                lines.append(f"{f.name.upper()} = {value!r}")
        lines.append(units_source(self))
        lines.append("USER_FORCE = None")
        # without user files, a stand-in the external forces' hook takes and never calls
        lines.append("from x3dpd.physics.external_force import no_user_force  # noqa: E402")
        lines.append("USER_FORCE = no_user_force if USER_FORCE is None else USER_FORCE")
        return "\n".join(lines)

    def name(self) -> str:
        """The generated module's file stem: the flags as bits, then the other fields."""
        flags = "".join("1" if getattr(self, f.name) else "0" for f in fields(self)
                        if f.type in ("bool", bool))
        rest = "_".join(str(getattr(self, f.name)) for f in fields(self)
                        if f.type not in ("bool", bool))
        # module names of the generated files: identifier characters only ("cylinder+capsule"
        # -> "cylinder_capsule")
        return re.sub(r"\W", "_", f"advance_{flags}_{rest}")

    def label(self) -> str:
        """A readable name of the variant: its effects joined by ``+`` -- each flag that is on,
        each other field that differs from its default as ``field=value`` (the shapes joined by
        commas) -- or ``"none"``; as unique as :meth:`name` (``walls+pairs+walls_translate``,
        ``walls+pairs+friction+friction_law=mindlin+normal_law=hooke``). The kernel cache's
        manifest, ``x3dpd cache``, the test suite's variant list (tests/meta/variants.txt) and
        the loops tests declare they ride (``pytest.mark.rides``) use it."""
        parts = []
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool):
                if value:
                    parts.append(f.name)
            elif value != f.default:
                text = value.replace("+", ",") if f.name == "shapes" else value
                parts.append(f"{f.name}={text}")
        return "+".join(parts) or "none"

    @classmethod
    def from_label(cls, label: str) -> "Variant":
        """The variant of a :meth:`label`; a ValueError names a part that is not one."""
        kinds = {f.name: f for f in fields(cls)}
        values: dict = {}
        for part in ([] if label.strip() == "none" else label.strip().split("+")):
            name, eq, text = part.partition("=")
            f = kinds.get(name)
            if f is None or (isinstance(f.default, bool) == bool(eq)):
                raise ValueError(f"{part!r} in variant label {label!r} is neither an effect "
                                 "flag nor field=value of a Variant field")
            if name in values:
                raise ValueError(f"{name} twice in variant label {label!r}")
            if isinstance(f.default, bool):
                values[name] = True
            elif isinstance(f.default, int):
                values[name] = int(text)
            else:
                values[name] = text.replace(",", "+") if name == "shapes" else text
        variant = cls(**values)
        variant.header()  # an unknown law or shape: a ValueError naming it
        if variant.label() != label.strip():
            raise ValueError(f"variant label {label!r} is not in canonical form: "
                             f"{variant.label()!r}")
        return variant


def _with_unit_flags(declared: type) -> type:
    """``Variant`` with a flag for every registered effect unit (x3dpd.physics.effect_units)
    that has no field above: a new unit's flag comes from its registration, appended after the
    declared fields in registry order (their labels and file stems unchanged), so adding a
    unit needs no edit here. The units declared above keep their documented fields."""
    names = {f.name for f in fields(declared)}
    extra = [(u.flag, bool, field(default=False)) for u in UNITS
             if not u.runtime and u.flag not in names]
    if not extra:
        return declared
    cls = make_dataclass("Variant", extra, bases=(declared,), frozen=True)
    cls.__module__, cls.__qualname__, cls.__doc__ = __name__, "Variant", declared.__doc__
    return cls


Variant = _with_unit_flags(Variant)


def _shapes_source(names: str) -> str:
    """``HAS_SHAPES`` and ``SHAPE_LOCATE``: the locators of the scene's analytic wall shapes,
    imported from their modules and chosen by kind (x3dpd.geometry.shapes)."""
    if not names:
        return "HAS_SHAPES = False\nSHAPE_LOCATE = None\nSHAPE_CLEAR = None"
    lines = ["HAS_SHAPES = True",
             "from x3dpd._jit import step_kernel as _shape_kernel  # noqa: E402"]
    calls, clears = [], []
    for name in names.split("+"):
        if name not in BY_SHAPE_NAME:
            raise ValueError(f"unknown analytic wall shape {name!r}; use one of "
                             f"{sorted(BY_SHAPE_NAME)}")
        kind = kind_of(name)
        module = BY_SHAPE_NAME[name].module
        lines.append(f"from {module} import locate_parts as _locate_shape_{kind}  # noqa: E402")
        calls.append((kind, f"_locate_shape_{kind}(x, na, nb, params, c, px, py, pz, r, out)"))
        if BY_SHAPE_NAME[name].clear_of is None:
            clears.append((kind, "return False"))
        else:
            lines.append(f"from {module} import clear_of as _clear_shape_{kind}  # noqa: E402")
            clears.append((kind, f"return _clear_shape_{kind}(x, na, nb, params, c, px, py, "
                                 "pz, r)"))
    return "\n".join(
        lines + ["", "", "@_shape_kernel",
                 "def SHAPE_LOCATE(kind, x, na, nb, params, c, px, py, pz, r, out):"]
        + _by_kind(calls) + ["", "", "@_shape_kernel",
                             "def SHAPE_CLEAR(kind, x, na, nb, params, c, px, py, pz, r):"]
        + _by_kind(clears) + (["    return False"] if len(clears) > 1 else []) + ["", ""])


def _by_kind(calls: list[tuple[int, str]]) -> list[str]:
    """A generated function's body: the one statement, or one branch per shape kind."""
    if len(calls) == 1:
        return [f"    {calls[0][1]}"]
    return [f"    {'if' if j == 0 else 'elif'} kind == {kind}:\n        {call}"
            for j, (kind, call) in enumerate(calls)]


def _friction_import(name: str) -> str:
    law = TANGENTIAL_LAWS[name]
    def alias(a: str) -> str:
        return "TANGENTIAL_" + a.upper() if a.islower() else _TANGENTIAL_CONSTANT[a]

    names = ", ".join([f"{law.force} as TANGENTIAL_FORCE"]
                      + [f"{a} as {alias(a)}" for a in TANGENTIAL_LAW_API])
    return f"from {law.module.__name__} import {names}"


def _rolling_import(name: str) -> str:
    law = ROLLING_LAWS[name]
    if law is None:   # the loop's HAS_ROLLING branches are deleted; the names stay defined
        return ("HAS_ROLLING = False\nN_ROLLING = 0\n"
                "from x3dpd.physics.epsd import rolling_torque as ROLLING_TORQUE")
    return (f"HAS_ROLLING = True\nfrom {law.__name__} import rolling_torque as ROLLING_TORQUE, "
            "N_HISTORY as N_ROLLING")


#: The loop's names of a tangential law's constants.
_TANGENTIAL_CONSTANT = {"N_HISTORY": "N_TANGENTIAL", "STORES_ENERGY": "TANGENTIAL_STORES"}


def _normal_import(name: str) -> str:
    names = ", ".join(f"{a} as NORMAL_{a.upper()}" for a in NORMAL_LAW_API)
    return f"from {NORMAL_LAWS[name].__name__} import {names}"


#: Law fields of a Variant: (registry, the VARIANT line importing a law into the loop).
_LAWS = {"friction_law": (TANGENTIAL_LAWS, _friction_import),
         "rolling_law": (ROLLING_LAWS, _rolling_import),
         "normal_law": (NORMAL_LAWS, _normal_import)}

_ROOT = Path(__file__).resolve().parents[1]


def kernel_sources() -> list[Path]:
    """Every x3dpd source file a compiled step loop is built from: the template, this factory,
    and every x3dpd module they import, followed through imports (the modules of all laws a
    variant may select are imported here). Editing any of them changes the cache key."""
    todo = [_TEMPLATE, Path(__file__).resolve(), _ROOT / "_jit.py"]
    seen: set[Path] = set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        for node in ast.walk(ast.parse(path.read_text())):
            names = []
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            for name in names:
                if name.split(".")[0] != "x3dpd":
                    continue
                rel = Path(*name.split(".")[1:])
                for cand in (_ROOT / rel.with_suffix(".py"), _ROOT / rel / "__init__.py"):
                    if cand.is_file():
                        todo.append(cand.resolve())
    return sorted(seen)


#: (the sources' (path, mtime, size) stamps, their hash) of the last :func:`_source_hash`
_HASHED: list = []


def _stamps(paths) -> tuple:
    out = []
    for path in paths:
        try:
            st = path.stat()
        except OSError:
            return ()
        out.append((path, st.st_mtime_ns, st.st_size))
    return tuple(out)


def _source_hash() -> str:
    """Hash of the kernel sources and the numba version (the cache folder's name).

    Walking and hashing the sources takes ~2 s of parsing; every Simulation asks (each point
    of a sweep or design), so the hash is kept while no source file has changed on disk (same
    modification times and sizes: an edit that adds an import changes its file too)."""
    if _HASHED and _stamps(p for p, _, _ in _HASHED[0]) == _HASHED[0]:
        return _HASHED[1]
    paths = kernel_sources()
    h = hashlib.sha256(numba.__version__.encode())
    for path in paths:
        h.update(path.relative_to(_ROOT).as_posix().encode())
        h.update(path.read_bytes())
    digest = h.hexdigest()[:16]
    _HASHED[:] = [_stamps(paths), digest]
    return digest


def cache_root() -> Path:
    """The kernel cache: ``$X3DPD_CACHE_DIR``, else ``$XDG_CACHE_HOME/x3dpd``, else
    ``~/.cache/x3dpd``. It holds ``kernels/<source hash>/`` (:func:`cache_dir`) and, beside
    those folders, the compile times of this machine (``kernels/compile_times.json``,
    x3dpd.solver.compile_log)."""
    base = os.environ.get("X3DPD_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "x3dpd")
    return Path(base)


def cache_dir() -> Path:
    """Folder of generated variants of these sources: ``kernels/<source hash>`` in
    :func:`cache_root`."""
    return cache_root() / "kernels" / _source_hash()


def source_hash() -> str:
    """The hash of the kernel sources and numba's version that names :func:`cache_dir`."""
    return _source_hash()


def variant_of(module_name: str):
    """``(Variant, file stem)`` of a loop module :func:`make_advance` made in this process, or
    None for any other module."""
    return _VARIANT_OF.get(module_name)


def variant_sources(variant: Variant) -> dict[str, str]:
    """Source text of each module of ``variant``, by part (:data:`PARTS`; ``""`` the loop):
    ``_template_variant.py`` with its VARIANT block replaced by the variant's constants, and
    the template's other files as they are."""
    out = {}
    for part in PARTS:
        text = _TEMPLATE.with_name(f"_template_{part}.py").read_text()
        if part == "variant":
            head, rest = text.split(_BEGIN, 1)
            _, tail = rest.split(_END, 1)
            text = f"{head}{_BEGIN}\n{variant.header()}\n{_END}{tail}"
        out[part] = text
    out[""] = _TEMPLATE.read_text()
    return out


def make_advance(variant: Variant, user_files=()):
    """The module implementing ``variant`` (its ``advance`` and ``_forces`` kernels).

    The loop and each part of the template (:data:`PARTS`) become files of the kernel cache
    named after the variant, whose imports of one another (``x3dpd.solver._template_<part>``)
    name their generated copies: numba compiles one variant from files of its own, and caches
    them on disk. ``user_files``: ``(path, NODE_INDEX)`` of each compiled user force file,
    called in order from the step (variant.user_force). Each becomes a cached copy, see
    :func:`_user_modules`.
    """
    user_files = tuple((os.fspath(p), np.ascontiguousarray(ix, np.int64)) for p, ix in user_files)
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    users = _user_modules(folder, user_files) if variant.user_force else ()
    key = (variant, users)
    if key in _LOADED:
        return _LOADED[key]
    sources = variant_sources(variant)
    stem = variant.name()
    if users:
        sources["variant"] = sources["variant"].replace(
            "\nUSER_FORCE = None\n", "\n" + _user_force_source(users) + "\n", 1)
        stem += "_" + hashlib.sha256(" ".join(users).encode()).hexdigest()[:12]
    name = f"x3dpd_kernels_{_source_hash()}_{stem}"
    module = None
    for part in PARTS + ("",):
        suffix = f"__{part}" if part else ""
        path = folder / f"{stem}{suffix}.py"
        _write_if_changed(path, sources[part].replace(_PART_MODULE, f"{name}__"))
        module = _import_file(f"{name}{suffix}", path)
    for unit in UNITS:   # the units' kernels the Python side calls on a state
        for kernel_name in unit.kernels:
            setattr(module, kernel_name, getattr(sys.modules[unit.module], kernel_name))
    _LOADED[key] = module
    _VARIANT_OF[name] = (variant, stem)
    return module


def part_module(module, part: str):
    """The generated module of one template part (:data:`PARTS`) of the loop ``module``."""
    return sys.modules[f"{module.__name__}__{part}"]


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
