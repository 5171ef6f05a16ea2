# Over 400 lines: the design file's schema: every table's keys, each checked at its line.
"""A design file (``x3dpd design SPEC``): one TOML file naming a structure deck, the design
variables to try and the evaluation (report Section 7.5, steps 3-6). Schema: docs/design.md.

:func:`read_design` parses and checks the whole file before anything is run: an unknown key, a
variable with no values, a value of the wrong kind, a material not in the library, a missing
deck are each an :class:`~x3dpd.errors.InputError` ``FILE:LINE: message`` at the offending
key's line. (Whether a fill fits is checked when the configurations are made, also before any
run, x3dpd.design.configs.)
"""

from __future__ import annotations

import itertools
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from x3dpd.design.config_mip import MIP_KEYS
from x3dpd.design.design_reader import Reader, key_lines
from x3dpd.design.levels import read_levels
from x3dpd.design.drive import LARGEST_LEVEL
from x3dpd.design.spec import AutoBand, parse_auto_band, parse_frequencies
from x3dpd.design.steady_state import Criterion
from x3dpd.errors import InputError

#: Keys of a configuration: fixed in [fill], varied in [vary], or set per [[configuration]].
CONFIG_KEYS = (
    "material",
    "radius",
    "count",
    "fill_ratio",
    "particle_mass",
    "cavities",
    "cavity_length",
    "cavity_size",
    "cavity_radius",
    "clearance",
    "packing",
    "gap",
    "gap_fraction",
    "jitter",
    "seed",
    "dt",
    "stiffness_scale",
    "temperature",
) + MIP_KEYS  # a multiple individual particle damper's plates (x3dpd.design.config_mip)
#: How many particles: at most one of these per configuration (none: the deck's count).
AMOUNT_KEYS = ("count", "fill_ratio", "particle_mass")
TOP_KEYS = (
    "title",
    "structure",
    "usrfrc_code",
    "mass_budget",
    "cavity",
    "fill",
    "vary",
    "configuration",
    "evaluate",
    "mip",
    "levels",
)
CAVITY_KEYS = ("set", "masters", "spacing")
EVALUATIONS = ("sweep", "dwell", "ringdown")
EVALUATE_KEYS = {
    "common": ("kind", "node", "dof", "drives", "baselines"),
    "sweep": (
        "frequencies",
        "direction",
        "tol",
        "window",
        "max_cycles",
        "samples_per_cycle",
        "extrapolate",
        "predict",
        "replicas",
    ),
    "dwell": (
        "frequency",
        "tol",
        "window",
        "max_cycles",
        "samples_per_cycle",
        "extrapolate",
        "predict",
        "replicas",
    ),
    "ringdown": ("drive_frequency", "drive_until", "ring"),
}


@dataclass(frozen=True)
class Configuration:
    """One configuration: its ``name`` and the values of the keys it sets (CONFIG_KEYS);
    ``varied`` the keys that differ between configurations (design.csv columns)."""

    name: str
    values: dict
    line: int = 0


@dataclass(frozen=True)
class Evaluation:
    """What is measured on every configuration (docs/design.md, [evaluate])."""

    kind: str
    drives: tuple[float, ...]
    frequencies: tuple[float, ...] = ()
    node: int | None = None
    dof: int | None = None
    direction: str | None = None
    baselines: tuple[str, ...] = ("undamped", "added-mass")
    criterion: Criterion = field(default_factory=Criterion)
    drive_until: float = 1.0
    ring: float = 2.0
    #: ``frequencies = "auto:LO:HI[:RES[:POINTS]]"``: search each peak (``frequencies`` empty)
    auto: AutoBand | None = None


@dataclass(frozen=True)
class DesignFile:
    """A parsed design file (see the module doc)."""

    path: Path
    title: str
    structure: Path
    usrfrc_code: bool
    mass_budget: float | None
    cavity_set: int | None
    cavity_masters: tuple[int, ...] | None
    cavity_spacing: tuple[float, float, float] | None
    configurations: tuple[Configuration, ...]
    varied: tuple[str, ...]
    evaluation: Evaluation
    text: str = ""
    #: ``[levels]``: the structure's own mode at each drive level (x3dpd.design.levels)
    levels: object = None

    def line_of(self, *keys) -> int:
        """The line of a key path in the file (0 when not found)."""
        return key_lines(self.text).get(tuple(keys), 0)

    def where(self, *keys) -> str:
        """``FILE:LINE`` of a key path, for messages."""
        line = self.line_of(*keys)
        return f"{self.path}:{line}" if line else str(self.path)


def read_design(path: str | Path) -> DesignFile:
    """Parse and check a design file (module doc); raises InputError at the bad line."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read the design file ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        line = path.read_bytes()[: exc.start].count(b"\n") + 1
        raise InputError(
            f"{path}:{line}: not a TOML file: byte {exc.object[exc.start]:#04x} is not UTF-8 "
            "text (a design file is TOML, UTF-8 text)"
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        at = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        where = f"{path}:{at.group(1)}:{at.group(2)}" if at else str(path)
        raise InputError(f"{where}: not a TOML file: {str(exc).split(' (at')[0]}") from None
    r = Reader(path, text)
    r.known(data, TOP_KEYS, ())
    if "structure" not in data:
        r.fail(("structure",), "missing: the structure deck (a path relative to this file)")
    if not isinstance(data["structure"], str):
        r.fail(("structure",), "expected the path of a deck")
    structure = (path.parent / data["structure"]).resolve()
    if not structure.is_file():
        r.fail(
            ("structure",), f"deck {data['structure']!r} does not exist (looked for {structure})"
        )
    cavity = _table(r, data, "cavity")
    r.known(cavity, CAVITY_KEYS, ("cavity",))
    cavity_set = (
        r.number(cavity["set"], ("cavity", "set"), integer=True) if "set" in cavity else None
    )
    masters = spacing = None
    if "masters" in cavity:
        masters = cavity["masters"]
        if not isinstance(masters, list) or not masters:
            r.fail(("cavity", "masters"), "expected a list of master node ids, one per cavity")
        masters = tuple(r.number(m, ("cavity", "masters"), integer=True) for m in masters)
    if "spacing" in cavity:
        spacing = cavity["spacing"]
        if not isinstance(spacing, list) or len(spacing) != 3:
            r.fail(("cavity", "spacing"), f"expected [dx, dy, dz], got {spacing!r}")
        spacing = tuple(float(r.number(v, ("cavity", "spacing"), positive=False)) for v in spacing)
    budget = data.get("mass_budget")
    if budget is not None:
        budget = r.number(budget, ("mass_budget",))
    usrfrc_code = data.get("usrfrc_code", False)
    if not isinstance(usrfrc_code, bool):
        r.fail(("usrfrc_code",), "expected true or false")
    configs, varied = _configurations(r, data)
    evaluation = _evaluation(r, _table(r, data, "evaluate", required=True))
    return DesignFile(
        path=path,
        title=str(data.get("title", path.stem)),
        structure=structure,
        usrfrc_code=usrfrc_code,
        mass_budget=budget,
        cavity_set=cavity_set,
        cavity_masters=masters,
        cavity_spacing=spacing,
        configurations=configs,
        varied=varied,
        evaluation=evaluation,
        text=text,
        levels=read_levels(r, _table(r, data, "levels"), evaluation),
    )


def _table(r: Reader, data: dict, name: str, required: bool = False) -> dict:
    value = data.get(name, {})
    if required and name not in data:
        r.fail((name,), f"missing: the [{name}] table (docs/design.md)")
    if not isinstance(value, dict):
        r.fail((name,), f"expected a table [{name}]")
    return value


def _configurations(r: Reader, data: dict) -> tuple[tuple[Configuration, ...], tuple[str, ...]]:
    """Every configuration: [fill] defaults, then each [[configuration]] (or one without), times
    every combination of the [vary] lists."""
    fixed = _table(r, data, "fill")
    r.known(fixed, CONFIG_KEYS, ("fill",))
    fixed = {k: r.config_value(k, v, ("fill", k)) for k, v in fixed.items()}
    mip = _table(r, data, "mip")
    r.known(mip, MIP_KEYS, ("mip",))
    for k, v in mip.items():
        if k in fixed:
            r.fail(("mip", k), f"{k} is also in [fill]")
        fixed[k] = r.config_value(k, v, ("mip", k))
    vary = _table(r, data, "vary")
    r.known(vary, CONFIG_KEYS, ("vary",))
    lists = {}
    for k, values in vary.items():
        if not isinstance(values, list):
            r.fail(("vary", k), f"expected a list of values, e.g. {k} = [1, 2]")
        if not values:
            r.fail(("vary", k), "a design variable with no values")
        lists[k] = [r.config_value(k, v, ("vary", k)) for v in values]
        if len(set(map(repr, lists[k]))) != len(values):
            r.fail(("vary", k), "a value is listed twice")
    explicit = data.get("configuration", [{}])
    if not isinstance(explicit, list) or not explicit:
        r.fail(("configuration",), "expected [[configuration]] tables")
    configs, names = [], {}
    for i, entry in enumerate(explicit):
        keys = ("configuration", i)
        r.known(entry, CONFIG_KEYS + ("name",), keys)
        own = {k: r.config_value(k, v, keys + (k,)) for k, v in entry.items() if k != "name"}
        for k in own:
            if k in lists:
                r.fail(keys + (k,), f"{k} is also a design variable in [vary]")
        for combo in itertools.product(*lists.values()):
            values = {**fixed, **own, **dict(zip(lists, combo))}
            amounts = [k for k in AMOUNT_KEYS if k in values]
            if len(amounts) > 1:
                r.fail(
                    keys if own else ("vary",),
                    f"give one of {', '.join(AMOUNT_KEYS)}, not {' and '.join(amounts)}",
                )
            if "gap" in values and "gap_fraction" in values:
                r.fail(keys if own else ("vary",), "give gap or gap_fraction, not both")
            if "clearance" in values and "cavity_length" in values:
                r.fail(keys if own else ("vary",), "give cavity_length or clearance, not both")
            name = entry.get("name") if not lists else None
            if name is None:
                label = "_".join(_label(k, v) for k, v in zip(lists, combo))
                name = "_".join(x for x in (entry.get("name"), label) if x) or f"config_{i + 1}"
            if not re.fullmatch(r"[\w.+-]+", str(name)):
                r.fail(
                    keys + ("name",),
                    f"name {name!r}: use letters, digits, . _ + - only (it names a folder)",
                )
            if name in names:
                r.fail(keys + ("name",), f"configuration name {name!r} given twice")
            names[name] = True
            configs.append(Configuration(str(name), values, _line(r, keys, lists)))
    varied = [k for k in CONFIG_KEYS if len({repr(c.values.get(k)) for c in configs}) > 1]
    return tuple(configs), tuple(varied)


def _line(r: Reader, keys: tuple, lists: dict) -> int:
    """The line a configuration's errors point at: its [[configuration]] table, else (made by
    [vary] alone) the first varied key's, else the [fill] table's."""
    line = r.lines.get(keys, 0)
    if not line and lists:
        line = r.lines.get(("vary", next(iter(lists))), 0)
    return line or r.lines.get(("fill",), 0)


def _label(key: str, value) -> str:
    short = {
        "material": "",
        "radius": "r",
        "count": "n",
        "fill_ratio": "fill",
        "particle_mass": "m",
        "cavities": "cav",
        "cavity_length": "L",
        "cavity_size": "box",
        "cavity_radius": "Rc",
        "clearance": "c",
        "packing": "",
        "gap": "gap",
        "gap_fraction": "gapf",
        "jitter": "jit",
        "seed": "seed",
        "dt": "dt",
        "stiffness_scale": "Ex",
        "holes": "holes",
        "pitch": "p",
        "hole": "hole",
        "thickness": "t",
        "shim": "shim",
        "plate_size": "W",
        "end_plate": "end",
        "lumped": "lumped",
        "start": "",
        "temperature": "T",
    }
    if isinstance(value, tuple):
        value = "x".join(f"{v:g}" for v in value)
    elif isinstance(value, float):
        value = f"{value:g}"
    return f"{short[key]}{value}"


# Over 80 lines: the [evaluate] table's keys, each checked at its line.
def _evaluation(r: Reader, ev: dict) -> Evaluation:
    keys = ("evaluate",)
    kind = ev.get("kind")
    if kind not in EVALUATIONS:
        r.fail(keys + ("kind",), f"expected kind = one of {', '.join(EVALUATIONS)}, got {kind!r}")
    r.known(ev, EVALUATE_KEYS["common"] + EVALUATE_KEYS[kind], keys)
    drives = ev.get("drives")
    if drives is None and kind != "ringdown":
        r.fail(keys, "missing: drives = [force amplitudes]")
    if drives is not None:
        if not isinstance(drives, list) or not drives:
            r.fail(keys + ("drives",), "expected a non-empty list of force amplitudes")
        drives = tuple(float(r.number(d, keys + ("drives",))) for d in drives)
        if max(drives) > LARGEST_LEVEL:
            r.fail(
                keys + ("drives",),
                f"a force amplitude of {max(drives):g} is beyond what a run can hold (at "
                f"most {LARGEST_LEVEL:g}: its energies would overflow double precision)",
            )
    node = ev.get("node")
    dof = ev.get("dof")
    if node is not None:
        node = r.number(node, keys + ("node",), integer=True)
    if dof is not None and dof not in (1, 2, 3):
        r.fail(keys + ("dof",), f"expected 1, 2 or 3 (a translation), got {dof!r}")
    baselines = ev.get("baselines", ["undamped", "added-mass"])
    from x3dpd.design.baselines import BASELINES

    if not isinstance(baselines, list) or any(b not in BASELINES for b in baselines):
        r.fail(keys + ("baselines",), f"expected a list of {', '.join(BASELINES)}")
    crit = {}
    for k in ("tol", "window", "max_cycles", "samples_per_cycle", "replicas"):
        if k in ev:
            crit[k] = r.number(ev[k], keys + (k,), integer=k != "tol")
    for k in ("extrapolate", "predict"):
        if k in ev:
            if not isinstance(ev[k], bool):
                r.fail(keys + (k,), "expected true or false")
            crit[k] = ev[k]
    criterion = Criterion(**crit)
    for name, must in criterion.problems()[:1]:
        where = keys + (name,) if name in ev else keys
        r.fail(where, f"{name} = {getattr(criterion, name)!r}: expected {must}")
    out = {
        "kind": kind,
        "drives": drives or (),
        "node": node,
        "dof": dof,
        "baselines": tuple(baselines),
        "criterion": criterion,
    }
    if kind == "sweep":
        freq = ev.get("frequencies")
        if freq is None:
            r.fail(keys, 'missing: frequencies = "START:STOP:STEP" or a list [Hz]')
        text = (
            freq
            if isinstance(freq, str)
            else ",".join(map(repr, freq))
            if isinstance(freq, list)
            else repr(freq)
        )
        try:
            out["auto"] = parse_auto_band(text)
            out["frequencies"] = () if out["auto"] else parse_frequencies(text)
        except InputError as exc:
            r.fail(keys + ("frequencies",), str(exc).replace("--freq ", ""))
        direction = ev.get("direction")
        if direction not in (None, "up", "down", "both"):
            r.fail(keys + ("direction",), "expected up, down or both")
        out["direction"] = direction
    elif kind == "dwell":
        if "frequency" not in ev:
            r.fail(keys, "missing: frequency = the dwell frequency [Hz]")
        out["frequencies"] = (float(r.number(ev["frequency"], keys + ("frequency",))),)
    else:
        for k in ("drive_until", "ring"):
            if k in ev:
                out[k] = float(r.number(ev[k], keys + (k,)))
        if "drive_frequency" in ev:
            out["frequencies"] = (
                float(r.number(ev["drive_frequency"], keys + ("drive_frequency",))),
            )
    return Evaluation(**out)
