"""The docs name only what the code has, and the README stays a manual.

docs/architecture.md and docs/engine.md describe the code by its names: module paths
(``x3dpd/solver/variants.py``, ``api/run_steps.py``), dotted names (``x3dpd._jit.StepLoopCompiler``,
``bundles.pack``, ``Simulation._bundles``), the loop's identifiers (``TANGENTIAL_FORCE``,
``_pair_filter``) and the registries' names. Each must exist: a module path is a file or
folder, a dotted name imports and has its attributes, an identifier is defined somewhere in the
package, and the registry table of docs/architecture.md lists exactly the code's keys. The
README is at most 350 lines, its quick start exactly two commands, the second of which
``.ci/run`` runs; the links of the README and of the docs resolve, anchors included. Each check
is also run on text made to fail (the ``test_the_check_*`` tests)."""

from __future__ import annotations

import ast
import importlib
import inspect
import re
import shlex
from functools import cache
from pathlib import Path

import pytest

from x3dpd.solver.bundles import ADVANCE_BUNDLES

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "x3dpd"
README = ROOT / "README.md"
ARCHITECTURE = ROOT / "docs" / "architecture.md"
ENGINE = ROOT / "docs" / "engine.md"
CODE_DOCS = (ARCHITECTURE, ENGINE)
#: Files whose links (and anchors) must resolve.
LINKED = (README, ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md")))
MAX_README_LINES = 350

#: The step loop's bundle arguments as the docs write them (``pairs.history``): argument name
#: (ADVANCE_BUNDLES, but ``units``: the effect units' bundles, each of its own class) -> class in
#: x3dpd.solver.bundles.
_BUNDLES = "Nodes RigidBodies Particles Faces ContactList ContactList Shapes"
BUNDLE_ARGUMENTS = dict(
    zip(
        (name for name in ADVANCE_BUNDLES if name != "units"),
        (*_BUNDLES.split(), "Stepping", "Output"),
        strict=True,
    )
)
#: Names the docs use that are not x3dpd's: numba's, LLVM's and the environment's.
NOT_OURS = {"NUMBA_OPT", "NUMBA_LLVM_PASS_TIMINGS", "NUMBA_NUM_THREADS", "LocalCluster"}

#: Package subfolders a doc may name without the ``x3dpd/`` prefix (``api/run_steps.py``).
SUBPACKAGES = tuple(p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file())
PATH = re.compile(r"(?<![\w./<-])((?:x3dpd|tests|tools|decks|docs|designs)/[\w./*<>-]*[\w*/>])")
SHORT_PATH = re.compile(rf"(?<![\w./<-])((?:{'|'.join(SUBPACKAGES)})/[\w./*<>-]*[\w*/>])")
FILE_SUFFIXES = (".py", ".md", ".toml", ".json", ".lark", ".inp", ".csv", ".png", ".txt")


@cache
def _package_modules() -> tuple[tuple[str, Path], ...]:
    """(dotted name, file) of every module of the package."""
    out = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        out.append((".".join(parts[:-1] if parts[-1] == "__init__" else parts), path))
    return tuple(out)


@cache
def _modules() -> dict[str, list[str]]:
    """Module basename -> the dotted names of the package's modules of that basename."""
    out: dict[str, list[str]] = {}
    for module, _ in _package_modules():
        out.setdefault(module.rsplit(".", 1)[-1], []).append(module)
    return out


@cache
def _identifiers() -> frozenset[str]:
    """Every name the package's and its tools' source defines or uses: functions, classes,
    variables, attributes, arguments, import aliases, and the string constants that are one
    identifier (registry keys, environment variables, option names, the benchmarks' scene
    names; not docstrings, which may name what no longer exists)."""
    names: set[str] = set()
    for path in (*PACKAGE.rglob("*.py"), *(ROOT / "tools").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            for field in ("id", "attr", "name", "arg"):
                value = getattr(node, field, None)
                if isinstance(value, str):
                    names.add(value)
            if isinstance(node, ast.alias):
                names.add(node.asname or node.name.split(".")[-1])
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                if re.fullmatch(r"[A-Za-z_]\w*", node.value):
                    names.add(node.value)
    return frozenset(names)


@cache
def _classes() -> dict[str, list[str]]:
    """Class name -> the modules (dotted) that define a class of that name."""
    out: dict[str, list[str]] = {}
    for module, path in _package_modules():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef):
                out.setdefault(node.name, []).append(module)
    return out


def _has_member(obj, name: str) -> bool:
    """``obj.name`` exists, or ``obj`` is a class whose instances set ``self.name``."""
    if hasattr(obj, name):
        return True
    if inspect.isclass(obj):
        fields = getattr(obj, "__dataclass_fields__", {}) or getattr(obj, "_fields", ())
        if name in fields:
            return True
        try:
            source = inspect.getsource(obj)
        except (OSError, TypeError):
            return False
        return re.search(rf"self\.{re.escape(name)}\s*(:[^=]*)?=", source) is not None
    return False


def _attributes(obj, names) -> bool:
    for name in names:
        if not _has_member(obj, name):
            return False
        obj = getattr(obj, name, None)
    return True


def _import(dotted: str):
    """(object, remaining attribute names) of the longest importable prefix of ``dotted``."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            return importlib.import_module(".".join(parts[:i])), parts[i:]
        except ImportError:
            continue
    return None, parts


def dotted_name_exists(dotted: str) -> bool | None:
    """Whether ``dotted`` names something of the package: ``x3dpd.module.name`` (imported),
    ``bundle_argument.field`` (``pairs.history``), ``Class.member`` or ``module.name`` (a
    module's basename). None: not the package's name (``math.sqrt``, ``pyproject.toml``)."""
    first, *rest = dotted.split(".")
    if first == "x3dpd":
        obj, remaining = _import(dotted)
        return obj is not None and _attributes(obj, remaining)
    if first in BUNDLE_ARGUMENTS:
        bundles = importlib.import_module("x3dpd.solver.bundles")
        return _attributes(getattr(bundles, BUNDLE_ARGUMENTS[first]), rest)
    candidates = [getattr(importlib.import_module(m), first) for m in _classes().get(first, ())]
    candidates += [importlib.import_module(m) for m in _modules().get(first, ())]
    if not candidates:
        return None
    return any(_attributes(obj, rest) for obj in candidates)


def _looks_like_code(word: str) -> bool:
    """An identifier a reader would take for the code's: snake_case with an underscore, ALL_CAPS,
    or CamelCase -- not a plain word (``threads``, ``x3dpd``)."""
    return (
        "_" in word.strip("_") or word.startswith("_") or (word.isupper() and len(word) > 1)
    ) or re.fullmatch(r"[A-Z][a-z0-9]+(?:[A-Z][a-z0-9]*)+", word) is not None


def _file_exists(name: str) -> bool:
    """A file of that name at the top of the repository or in x3dpd/, tools/ or tests/."""
    tops = (PACKAGE, ROOT / "tools", ROOT / "tests")
    return (ROOT / name).is_file() or any(any(top.rglob(name)) for top in tops)


def _prose(text: str) -> str:
    """A Markdown text without its fenced code blocks."""
    return re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)


def _inline_code(text: str) -> list[str]:
    """The doc's inline code spans (fenced blocks left out; a span may run over a line end)."""
    return [" ".join(span.split()) for span in re.findall(r"`([^`]+)`", _prose(text))]


def path_problems(text: str, short_paths: bool = False) -> list[str]:
    """Paths of the repository named in ``text`` that do not exist (``short_paths``: also
    ``api/...``, ``solver/...`` as paths under x3dpd/)."""
    found = [(p, p) for p in PATH.findall(text)]
    if short_paths:
        found += [(p, f"x3dpd/{p}") for p in SHORT_PATH.findall(text)]
    bad = []
    for shown, path in found:
        if "<" in path:
            continue
        path = path.rstrip("/.")
        exists = any(ROOT.glob(path)) if "*" in path else (ROOT / path).exists()
        if not exists:
            bad.append(f"{shown}: no such file or folder")
    return bad


def name_problems(text: str) -> list[str]:
    """Names in the inline code of ``text`` that the package does not have."""
    bad = []
    for span in _inline_code(text):
        m = re.match(r"[A-Za-z_][\w.]*", span)
        if not m or span[m.end() : m.end() + 1] in ("*", "/"):
            continue  # a path, a pattern (``tan_*``), an option, prose
        name = m.group().rstrip(".")
        if name.endswith(FILE_SUFFIXES):
            if "/" not in span and not _file_exists(name):
                bad.append(f"`{span}`: no file {name} in the repository")
            continue
        if "." in name:
            if dotted_name_exists(name) is False:
                bad.append(f"`{span}`: {name} does not exist")
        elif _looks_like_code(name) and name not in NOT_OURS and name not in _identifiers():
            bad.append(f"`{span}`: the package has no name {name}")
    return bad


def registry_rows(text: str) -> list[tuple[str, list[str]]]:
    """(registry, names) of the table under the doc's "## Registries" heading."""
    section = text.split("## Registries", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not cells[0].startswith("`x3dpd."):
            continue
        rows.append((cells[0].strip("`"), re.findall(r"`([^`]+)`", cells[1])))
    return rows


def registry_keys(dotted: str) -> list[str]:
    """The names a registry holds: a dict's keys, a tuple's strings or its items' ``name``."""
    obj, rest = _import(dotted)
    for name in rest:
        obj = getattr(obj, name)
    if isinstance(obj, dict):
        return list(obj)
    return [item if isinstance(item, str) else item.name for item in obj]


def registry_problems(text: str) -> list[str]:
    bad = []
    for registry, names in registry_rows(text):
        try:
            keys = registry_keys(registry)
        except (AttributeError, TypeError):
            bad.append(f"{registry}: no such registry")
            continue
        if sorted(keys) != sorted(names):
            bad.append(f"{registry}: the doc lists {names}, the code holds {keys}")
    return bad


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    text = _prose(path.read_text())
    seen: dict[str, int] = {}
    out = set()
    for heading in re.findall(r"^#{1,6} (.+)$", text, flags=re.M):
        base = slug(heading)
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def link_problems(path: Path) -> list[str]:
    text = _prose(path.read_text())
    bad = []
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue  # https:, mailto:
        file, _, anchor = target.partition("#")
        dest = (path.parent / file).resolve() if file else path
        if not dest.exists():
            bad.append(f"{path.name}: ({target}): no such file")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            bad.append(f"{path.name}: ({target}): no heading #{anchor} in {dest.name}")
    return bad


def quick_start_commands(text: str) -> list[str]:
    """The commands of the README's quick start: the first code block after its heading."""
    section = text.split("## Quick start", 1)[1]
    block = re.search(r"```\w*\n(.*?)```", section, flags=re.S).group(1)
    return [line.strip() for line in block.splitlines() if line.strip() and line[0] != "#"]


def _normalized(command: str) -> list[str]:
    """A shell command's words as the README writes them: ``python3 -m pip`` is ``pip``,
    ``python3`` is ``python``, quiet flags dropped."""
    words = command.replace("python3 -m pip", "pip").replace("python3", "python")
    return [w for w in shlex.split(words) if w not in ("-q", "--quiet")]


def ci_runs(command: str, ci_text: str) -> bool:
    want = _normalized(command)
    return any(
        _normalized(line) == want
        for line in ci_text.splitlines()
        if line.strip() and not line.lstrip().startswith("#")
    )


@pytest.mark.parametrize("doc", CODE_DOCS, ids=lambda p: p.name)
def test_every_path_a_code_doc_names_exists(doc):
    assert not path_problems(doc.read_text(), short_paths=True)


@pytest.mark.parametrize("doc", CODE_DOCS, ids=lambda p: p.name)
def test_every_name_a_code_doc_names_exists(doc):
    assert not name_problems(doc.read_text())


def test_the_registries_in_architecture_md_are_the_codes():
    text = ARCHITECTURE.read_text()
    listed = {registry for registry, _ in registry_rows(text)}
    for registry in (
        "x3dpd.physics.normal_laws.NORMAL_LAWS",
        "x3dpd.physics.tangential_laws.TANGENTIAL_LAWS",
        "x3dpd.physics.rolling.ROLLING_LAWS",
        "x3dpd.geometry.shapes.BY_SHAPE_NAME",
        "x3dpd.physics.effect_units.BY_UNIT_NAME",
        "x3dpd.deck.text_cards.BY_TEXT_TERMINAL",
    ):
        assert registry in listed, f"docs/architecture.md's registry table lacks {registry}"
    assert not registry_problems(text)


@pytest.mark.parametrize("doc", LINKED, ids=lambda p: p.name)
def test_links_resolve(doc):
    assert not link_problems(doc)


@pytest.mark.parametrize("doc", (README, ROOT / "docs" / "performance.md"), ids=lambda p: p.name)
def test_the_x3dpd_names_and_paths_of_the_manual_exist(doc):
    text = doc.read_text()
    assert not path_problems(text)
    bad = [s for s in _inline_code(text) if s.startswith("x3dpd.")]
    assert not [s for s in bad if dotted_name_exists(re.match(r"[\w.]+", s).group()) is False]


def test_the_readme_is_a_manual_with_a_two_command_quick_start():
    text = README.read_text()
    assert len(text.splitlines()) <= MAX_README_LINES
    commands = quick_start_commands(text)
    assert len(commands) == 2, commands
    assert "pytest" in commands[1]
    assert ci_runs(commands[1], (ROOT / ".ci" / "run").read_text()), (
        ".ci/run must run the README's test command"
    )


def test_the_check_flags_a_path_that_does_not_exist():
    assert path_problems("in `x3dpd/solver/nowhere.py` and `api/gone.py`", short_paths=True) == [
        "x3dpd/solver/nowhere.py: no such file or folder",
        "api/gone.py: no such file or folder",
    ]
    assert not path_problems("`x3dpd/solver/variants.py`, `api/run_steps.py`, `model/build_*.py`")


def test_the_check_flags_names_that_do_not_exist():
    text = (
        "`friction_law` -> `FRICTION_LAW`; `x3dpd.solver.variants.make_everything`; "
        "`bundles.unpack`; `pairs.nothing`; `Simulation.no_such_member`; `_no_such_kernel`"
    )
    assert len(name_problems(text)) == 6, name_problems(text)
    good = (
        "`TANGENTIAL_FORCE`, `x3dpd._jit.StepLoopCompiler`, `bundles.pack`, `pairs.history`, "
        "`Simulation.energy_columns`, `_pair_filter`, `math.sqrt(v)`, `tan_*[..., 1]`, `threads`"
    )
    assert not name_problems(good), name_problems(good)


def test_the_check_flags_a_registry_that_differs_from_the_codes():
    table = (
        "## Registries\n\n| registry | names |\n|---|---|\n"
        "| `x3dpd.physics.rolling.ROLLING_LAWS` | `none`, `epsd`, `spin` |\n"
        "| `x3dpd.geometry.shapes.BY_SHAPE_NAME` | `cylinder` |\n"
        "| `x3dpd.physics.nowhere.LAWS` | `a` |\n"
    )
    assert len(registry_problems(table)) == 3, registry_problems(table)


def test_the_check_flags_a_broken_link(tmp_path):
    (tmp_path / "a.md").write_text("# Top\n\n## A heading, with `code`\n")
    doc = tmp_path / "b.md"
    doc.write_text("[ok](a.md#a-heading-with-code) [no](a.md#gone) [none](c.md)\n")
    assert len(link_problems(doc)) == 2, link_problems(doc)


def test_the_check_tells_the_ci_command_from_another():
    ci = 'python3 -m pip install -q -e ".[test]" && python3 -m pytest -n auto -q\n'
    assert ci_runs('pip install -e ".[test]" && python -m pytest -n auto', ci)
    assert not ci_runs('pip install -e ".[test]" && python -m pytest -n 1', ci)
