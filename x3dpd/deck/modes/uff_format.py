"""Normal modes from a universal file (UFF/UNV), read with pyuff.

What is read: every dataset 55 ("data at nodes") of analysis type 2 (normal mode), one per mode:
its mode number, frequency [Hz], modal mass, modal viscous damping ratio and, per node, 3 values
(x y z; data characteristic 2) or 6 (x y z rx ry rz; characteristic 3). Datasets 55 of other
analysis types and all other datasets are skipped. A node a mode's record leaves out is 0 there
(the format's note 9: all-zero records need not appear); a 3-value record's rotations are NaN.
A file always has the modal mass and damping fields: when every mode's is 0 the file is taken not
to give them (None). The hysteretic damping ratio is not read (a warning says so when nonzero).

Units come from dataset 164 when there is one: length and force from its units code (1 SI m N,
2 BG ft lbf, 7 IN in lbf) or, for other codes, from its factors (file units per SI unit) when
they match x3dpd's units; time is seconds. A system x3dpd cannot name (kgf, poundal, mN, cN) is an
error: convert the file, or remove the dataset 164 and say the units on the card.
Values in dataset 55 are written as E13.5: 6 significant digits.
"""

from __future__ import annotations

import warnings

import numpy as np

from x3dpd.errors import ModeFileError
from x3dpd.deck.modes.modeset import ModeSet, sorted_mode_set

#: Names of common datasets, for saying what a file holds.
DATASET_NAMES = {
    15: "nodes",
    18: "coordinate systems",
    55: "data at nodes",
    58: "function at nodal DOF",
    82: "trace lines",
    151: "header",
    164: "units",
    1858: "function header",
    2400: "model header",
    2411: "nodes",
    2412: "elements",
    2414: "analysis data",
    2420: "coordinate systems",
    2429: "permanent groups",
    2467: "permanent groups",
}

#: Dataset 164 units codes x3dpd can name: code -> (length, force).
UNIT_CODES = {1: ("m", "N"), 2: ("ft", "lbf"), 7: ("in", "lbf")}
#: Dataset 164 factors (file units per SI unit) of x3dpd's lengths and forces.
LENGTH_FACTORS = {"m": 1.0, "cm": 100.0, "mm": 1000.0, "in": 1.0 / 0.0254, "ft": 1.0 / 0.3048}
FORCE_FACTORS = {"N": 1.0, "kN": 1e-3, "dyn": 1e5, "lbf": 1.0 / 4.4482216152605}

_ANALYSIS = {
    0: "unknown",
    1: "static",
    2: "normal mode",
    3: "complex eigenvalue",
    4: "transient",
    5: "frequency response",
    6: "buckling",
    7: "complex eigenvalue",
}


class ModeFileWarning(UserWarning):
    """A mode file gives something x3dpd does not use."""


def read_modes_uff(path) -> ModeSet:
    """Read the normal modes of a universal file; every problem is a ModeFileError."""
    try:
        import pyuff
    except ImportError as e:
        raise ModeFileError(
            path, f"reading universal files needs pyuff ({e}); install it with: pip install pyuff"
        ) from None
    try:
        uff = pyuff.UFF(str(path))
        types = [int(t) for t in uff.get_set_types()]
    except Exception as e:  # noqa: BLE001 -- pyuff raises bare Exception
        raise ModeFileError(path, f"pyuff cannot read it as a universal file ({e})") from None
    if not types:
        raise ModeFileError(
            path,
            "no universal-file datasets (no '    -1' delimited blocks); "
            "expected a UFF/UNV file with dataset 55 (normal modes)",
        )
    modes_at = [i for i, t in enumerate(types) if t == 55]
    if not modes_at:
        raise ModeFileError(
            path,
            f"no dataset 55 (normal modes); it holds {_held(types)}. "
            "Expected dataset 55 records of analysis type 2, one per mode",
        )
    records = _read(uff, path, modes_at, 55)
    normal = [r for r in records if int(r.get("analysis_type", -1)) == 2]
    if not normal:
        kinds = sorted({_ANALYSIS.get(int(r.get("analysis_type", -1)), "?") for r in records})
        raise ModeFileError(
            path,
            f"its datasets 55 are {', '.join(kinds)} data; expected analysis type 2 (normal mode)",
        )
    units = _units(path, _read(uff, path, [i for i, t in enumerate(types) if t == 164], 164))
    return _mode_set(path, normal, units)


def _read(uff, path, indices, number) -> list[dict]:
    if not indices:
        return []
    try:
        sets = uff.read_sets(indices)
    except Exception as e:  # noqa: BLE001 -- pyuff raises bare Exception
        raise ModeFileError(
            path,
            f"a dataset {number} cannot be read ({e}); expected the layout of dataset {number}",
        ) from None
    return [sets] if isinstance(sets, dict) else list(sets)


def _mode_set(path, records, units) -> ModeSet:
    modes, freq, mass, damp, hyst, columns = [], [], [], [], [], []
    for r in records:
        mode = int(r["mode_n"])
        if int(r.get("data_type", 2)) != 2:
            raise ModeFileError(
                path, f"mode {mode} has complex values; expected real normal modes (data type 2)"
            )
        ndv = int(r.get("n_data_per_node", 0))
        if int(r.get("data_ch", 0)) not in (2, 3) or ndv not in (3, 6):
            raise ModeFileError(
                path,
                f"mode {mode} gives {ndv} values per node (data "
                f"characteristic {r.get('data_ch')}); expected 3 (x y z) "
                "or 6 (x y z rx ry rz)",
            )
        nodes = np.asarray(r["node_nums"], dtype=np.int64).reshape(-1)
        values = (
            np.column_stack(
                [np.asarray(r[f"r{k}"], dtype=np.float64).reshape(-1) for k in range(1, ndv + 1)]
            )
            if len(nodes)
            else np.zeros((0, ndv))
        )
        uniq, counts = np.unique(nodes, return_counts=True)
        if (counts > 1).any():
            raise ModeFileError(
                path,
                f"node {uniq[counts > 1][0]} appears more than once in "
                f"mode {mode}'s dataset 55; expected each node once",
            )
        if not np.isfinite(values).all():
            k = np.argwhere(~np.isfinite(values))[0]
            raise ModeFileError(
                path,
                f"mode {mode} has value {values[k[0], k[1]]} at node "
                f"{nodes[k[0]]}; expected finite numbers",
            )
        modes.append(mode)
        freq.append(float(r["freq"]))
        mass.append(float(r.get("modal_m", 0.0)))
        damp.append(float(r.get("modal_damp_vis", 0.0)))
        hyst.append(float(r.get("modal_damp_his", 0.0)))
        columns.append((nodes, values))
    node_ids = np.unique(np.concatenate([n for n, _ in columns]))
    if len(node_ids) == 0:
        raise ModeFileError(
            path, "its dataset 55 records give no node values; expected at least one node"
        )
    shapes = np.zeros((len(modes), len(node_ids), 6))
    for m, (nodes, values) in enumerate(columns):
        shapes[m, :, values.shape[1] :] = np.nan
        shapes[m, np.searchsorted(node_ids, nodes), : values.shape[1]] = values
    if any(h != 0.0 for h in hyst):
        warnings.warn(
            f"{path}: modal hysteretic damping ratios are not read (only the viscous "
            "damping ratios)",
            ModeFileWarning,
            stacklevel=3,
        )
    mass_a, damp_a = np.array(mass), np.array(damp)
    return sorted_mode_set(
        str(path),
        modes,
        freq,
        node_ids,
        shapes,
        damping=None if not damp_a.any() else damp_a,
        modal_mass=None if not mass_a.any() else mass_a,
        units=units,
    )


def _units(path, records) -> tuple[str, str, str] | None:
    found = {_system(path, r) for r in records}
    if len(found) > 1:
        units = "; ".join(" ".join(u) for u in sorted(found))
        raise ModeFileError(
            path, f"its datasets 164 declare different units ({units}); expected one"
        )
    return found.pop() if found else None


def _system(path, r) -> tuple[str, str, str]:
    code = int(r.get("units_code", 0))
    if code in UNIT_CODES:
        return (*UNIT_CODES[code], "s")
    length = _match(r.get("length"), LENGTH_FACTORS)
    force = _match(r.get("force"), FORCE_FACTORS)
    if length is None or force is None:
        desc = str(r.get("units_description", "")).strip()
        raise ModeFileError(
            path,
            f"dataset 164 declares units code {code}"
            f"{' (' + desc + ')' if desc else ''} with length factor "
            f"{r.get('length')} and force factor {r.get('force')}, which "
            "x3dpd cannot name; expected lengths m, cm, mm, in, ft and "
            "forces N, kN, dyn, lbf (convert the file, or remove the "
            "dataset 164)",
        )
    return (length, force, "s")


def _match(factor, table) -> str | None:
    try:
        factor = float(factor)
    except (TypeError, ValueError):
        return None
    # Factors are often written with 6 significant digits (3.28084); 1e-5 tells them apart.
    hits = [name for name, f in table.items() if abs(factor - f) <= 1e-5 * f]
    return hits[0] if hits else None


def _held(types) -> str:
    counts = {}
    for t in types:
        counts[t] = counts.get(t, 0) + 1
    return ", ".join(
        (f"{n} datasets {t}" if n > 1 else f"dataset {t}")
        + (f" ({DATASET_NAMES[t]})" if t in DATASET_NAMES else "")
        for t, n in counts.items()
    )
