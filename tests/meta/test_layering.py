"""The package imports only downward: cli -> testlab -> (design | study) -> api -> deck | model |
solver | io | analysis -> physics | geometry -> materials -> (errors, units, _jit). ``materials``
(the material library) sits just above the bottom: anything may import it, it imports only the
bottom layer. Imports under ``if TYPE_CHECKING:`` do not count (no runtime edge).
``x3dpd/__init__.py`` is the public facade: it may load the API (lazily, in its ``__getattr__``)
and nothing else above the bottom layer. Above the API nothing touches what a layer below keeps
private (a ``._name`` of anything but ``self``, a ``_name`` imported from another package)."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "x3dpd"
LAYER = {
    "cli": 5,
    "testlab": 4.5,
    "design": 4,
    "study": 4,
    "api": 3,
    "deck": 2,
    "model": 2,
    "solver": 2,
    "io": 2,
    "analysis": 2,
    "physics": 1,
    "geometry": 1,
    "materials": 0.5,
    "errors": 0,
    "units": 0,
    "_jit": 0,
    "_files": 0,
    "__init__": 0,
    "__main__": 6,
}
#: What the facade ``x3dpd/__init__.py`` may import (lazily) besides the bottom layer.
FACADE = {"api"}
#: Modules kept for one release at their old home, each only re-exporting its new one (an
#: upward import that nothing else may make): the test-lab modules that left x3dpd.design.
SHIMS = {
    f"design/{name}.py": f"x3dpd.testlab.{name}"
    for name in ("frf", "fit", "modal_fit", "trace_signals")
}


def _group(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "x3dpd":
        return None
    return parts[1] if len(parts) > 1 else "__init__"


def _runtime_imports(tree: ast.AST):
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in ast.walk(node):
                skip.add(id(sub))
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.lineno, node.module
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name


def test_imports_go_downward_only():
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        here = rel.parts[0].removesuffix(".py")
        for line, module in _runtime_imports(ast.parse(path.read_text())):
            there = _group(module)
            if there is None or there == here:
                continue
            if here == "__init__" and there in FACADE:
                continue
            if SHIMS.get(rel.as_posix()) == module:
                continue
            if LAYER[there] >= LAYER[here]:
                bad.append(f"x3dpd/{rel}:{line}: {here} imports {module}")
    assert not bad, "imports that do not go downward:\n" + "\n".join(bad)


#: What each tool above the API may import from the package (docs/architecture.md, "The
#: layers"): the CLI reaches the library only through ``x3dpd.api``; ``study``, ``design`` and
#: ``testlab`` likewise (design never drives the step loop itself: it goes through
#: x3dpd.api.run and x3dpd.api.stepper, and reads decks, models, traces and figures through
#: x3dpd.api's re-exports).
ABOVE_API = {
    "cli": {"cli", "api", "testlab", "design", "study", "errors", "units", "materials", "__init__"},
    "testlab": {
        "testlab",
        "design",
        "api",
        "errors",
        "units",
        "materials",
        "_jit",
        "_files",
        "__init__",
    },
    "study": {"study", "api", "errors", "units", "materials", "_jit", "_files", "__init__"},
    "design": {"design", "api", "errors", "units", "materials", "_jit", "_files", "__init__"},
}


def _beside_the_api(tool: str, source: str, name: str) -> list[str]:
    """The imports in ``source`` (a module of ``tool``) of groups the tool may not import."""
    return [
        f"{name}:{line}: {tool} imports {module}"
        for line, module in _runtime_imports(ast.parse(source))
        if (group := _group(module)) is not None and group not in ABOVE_API[tool]
    ]


def test_the_tools_above_the_api_go_through_it():
    bad = []
    for tool in ABOVE_API:
        for path in sorted((PACKAGE / tool).rglob("*.py")):
            if path.relative_to(PACKAGE).as_posix() in SHIMS:
                continue  # its one import is checked by test_a_shim_may_only_re_export_...
            bad += _beside_the_api(tool, path.read_text(), f"x3dpd/{path.relative_to(PACKAGE)}")
    assert not bad, "imports that bypass x3dpd.api:\n" + "\n".join(bad)


#: What is left to route through x3dpd.api: the design modules that still import a layer below
#: it, and which. A ratchet, now empty: a module not listed here, or a layer not listed for it,
#: fails (tests/meta/test_layering.py::test_the_ratchet_catches_a_new_import_below_the_api).
DESIGN_LEFT: dict[str, set[str]] = {}


def _design_below(name: str, source: str) -> list[str]:
    """The imports in ``source`` (x3dpd/design/``name``) of a layer below the API that
    :data:`DESIGN_LEFT` does not allow."""
    below = {group for group, layer in LAYER.items() if 0.5 < layer < LAYER["api"]}
    left = DESIGN_LEFT.get(name, set())
    return [
        f"x3dpd/design/{name}:{line}: design imports {module}"
        for line, module in _runtime_imports(ast.parse(source))
        if (group := _group(module)) in below and group not in left
    ]


def test_design_reaches_below_the_api_no_further_than_it_did():
    bad = []
    for path in sorted((PACKAGE / "design").rglob("*.py")):
        bad += _design_below(path.name, path.read_text())
    assert not bad, (
        "design modules that import below x3dpd.api (use or add a re-export in "
        "x3dpd/api/):\n" + "\n".join(bad)
    )


def test_the_ratchet_catches_a_new_import_below_the_api():
    for line in (
        "from x3dpd.deck.cards import Deck",
        "import x3dpd.model.build",
        "def f():\n    from x3dpd.analysis.frf import estimate_frf",
    ):
        assert _design_below("configs.py", line), line
        assert _beside_the_api("design", line, "x3dpd/design/configs.py"), line
    assert not _design_below("configs.py", "from x3dpd.api.decks import Deck")
    assert not _design_below(
        "configs.py", "if TYPE_CHECKING:\n    from x3dpd.model.model import Model"
    )


def test_a_cli_import_below_the_api_is_caught():
    # the check above must fail on each way of writing such an import, lazy ones included
    for line in (
        "from x3dpd.model.build import build_model",
        "import x3dpd.solver.simulation",
        "def f():\n    from x3dpd.io.trace import read_trace",
    ):
        assert _beside_the_api("cli", line, "x3dpd/cli/new.py"), line
    assert _beside_the_api("design", "from x3dpd.solver.simulation import Simulation", "d.py")
    assert not _beside_the_api("cli", "from x3dpd.api.decks import read_deck", "x3dpd/cli/new.py")
    assert not _beside_the_api(
        "cli", "if TYPE_CHECKING:\n    from x3dpd.model.model import Model", "x3dpd/cli/new.py"
    )


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _private_uses(tool: str, source: str, name: str) -> list[str]:
    """Where ``source`` (a module of ``tool``, above the API) touches a private name of a layer
    below or beside it: an attribute ``._name`` of anything but ``self`` or ``cls`` (a
    Simulation's kernels, its bundles, a state's internals), ``getattr(obj, "_name")``, or a
    ``_name`` imported from an x3dpd package other than ``tool``."""
    bad = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            if not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
                bad.append(f"{name}:{node.lineno}: {tool} touches {ast.unparse(node)}")
        elif (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("getattr", "setattr", "hasattr")
            and len(node.args) > 1
            and isinstance(node.args[1], ast.Constant)
            and isinstance(node.args[1].value, str)
            and _private(node.args[1].value)
        ):
            bad.append(f"{name}:{node.lineno}: {tool} touches {ast.unparse(node)}")
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            group = _group(node.module)
            if group is None or group == tool:
                continue
            for alias in node.names:
                if _private(alias.name):
                    bad.append(
                        f"{name}:{node.lineno}: {tool} imports {alias.name} from {node.module}"
                    )
    return bad


def test_nothing_above_the_api_touches_a_private_name_below_it():
    bad = []
    for tool in ABOVE_API:
        for path in sorted((PACKAGE / tool).rglob("*.py")):
            bad += _private_uses(tool, path.read_text(), f"x3dpd/{path.relative_to(PACKAGE)}")
    assert not bad, (
        "private names used above x3dpd.api (give the layer below a public operation, "
        "x3dpd/solver/placement.py for the step loop's state):\n" + "\n".join(bad)
    )


def test_a_private_name_above_the_api_is_caught():
    # each way the predicted start once reached into the step loop, and the other spellings
    for line in (
        "sim.kernels._update_slaves(x, v)",
        "b = sim._bundles()",
        "sim.kernels._modal_place(b['modal'])",
        "n = getattr(sim, '_load_seconds', 0.0)",
        "from x3dpd.api.stepper import _private_helper",
        "from x3dpd.design.sweep_table import _cell",
    ):
        assert _private_uses("testlab", line, "x3dpd/testlab/new.py"), line
    assert _private_uses("design", "sim.state._sc = None", "x3dpd/design/new.py")
    for line in (
        "self._cache = {}",
        "cls._registry[name] = x",
        "name = sim.kernels.__name__",
        "from x3dpd.design.sweep_table import _cell",  # its own package
        "from x3dpd.api.stepper import place_modes",
    ):
        assert not _private_uses("design", line, "x3dpd/design/new.py"), line


def test_a_shim_may_only_re_export_its_new_home():
    for rel, target in SHIMS.items():
        tree = ast.parse((PACKAGE / rel).read_text())
        body = [n for n in tree.body if not isinstance(n, ast.Expr)]  # the docstring
        assert len(body) == 1 and isinstance(body[0], ast.ImportFrom), rel
        assert body[0].module == target and body[0].names[0].name == "*", rel
