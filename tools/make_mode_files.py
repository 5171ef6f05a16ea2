#!/usr/bin/env python3
"""Write the mode-file fixtures ``tests/fixtures/modes/`` from two analytic models.

    python tools/make_mode_files.py [--out DIR]

(a) ``chain3``: three equal masses m on a line joined by three equal springs k, the first spring
    to ground (fixed-free), moving along x; SI units. Closed form: omega_j = 2 sqrt(k/m)
    sin((2j-1) pi / (2(2n+1))), phi_ij ~ sin(i (2j-1) pi / (2n+1)).
(b) ``cantilever``: a steel bar of rectangular section along x, clamped at node 1, in
    Euler-Bernoulli beam elements (cubic Hermite, consistent mass) bending in y (v, rz = dv/dx)
    and in z (w, ry = -dw/dx); inch-lbf-s units. Its first four modes.

Modes are solved with ``x3dpd.deck.modes.modes_from_matrices`` (scipy.linalg.eigh; shapes
mass-normalised, the component of largest magnitude positive). Each model is written as:

- ``NAME.op2``: a Nastran-style OP2 (MSC header, LAMA eigenvalue summary with generalized mass 1
  and stiffness omega^2, OUGV1 real eigenvectors with table code 7; 32-bit floats), written with
  pyNastran 1.4.1's own table writers. Its ``OP2.write_op2`` is not used because in 1.4.1 it
  skips the LAMA table and labels an eigenvector table as displacements (table code 1) -- with
  numpy 1.26 as with 2.4. Every node carries all six components, 0 where the model has no
  freedom (as Nastran writes constrained components), the clamped root node included.
- ``NAME.uff``: dataset 164 (units) and one dataset 55 (normal mode, analysis type 2) per mode,
  written with pyuff: 3 values per node for the chain (with damping ratios 0.01, 0.02, 0.03),
  6 for the cantilever.
- ``chain3.csv``: the chain in x3dpd's CSV layout (an example of it).

The output is deterministic (a fixed OP2 date); tests/io/test_modal_files.py reads it back.
"""

from __future__ import annotations

import argparse
import io
import sys
from pathlib import Path
from struct import Struct

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from x3dpd.deck.modes import ModeSet, modes_from_matrices, write_modes_csv  # noqa: E402
from x3dpd.deck.modes.op2_format import numpy_in1d_for_import  # noqa: E402

#: (a) the chain: mass [kg], stiffness [N/m], node ids, damping ratios written to the UFF file.
CHAIN = {"m": 2.0, "k": 1.0e4, "nodes": (10, 20, 30), "damping": (0.01, 0.02, 0.03)}
#: (b) the cantilever [in, lbf, s]: length, width along y, height along z, Young's modulus,
#: density (0.283 lbf/in^3 / 386.1 in/s^2), elements, modes kept. Node i stands at
#: x = (i - 1) L / elements; node 1 is clamped.
CANTILEVER = {
    "L": 10.0,
    "b": 1.0,
    "h": 0.5,
    "E": 3.0e7,
    "rho": 7.32971e-4,
    "elements": 5,
    "modes": 4,
}
OP2_DATE = (1, 1, 2025)


def chain_modes() -> ModeSet:
    """Modes of the fixed-free chain (x only)."""
    n, k, m = len(CHAIN["nodes"]), CHAIN["k"], CHAIN["m"]
    K = k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = k
    return modes_from_matrices(
        K,
        m * np.eye(n),
        CHAIN["nodes"],
        ["x"] * n,
        damping=CHAIN["damping"],
        units=("m", "N", "s"),
        name="chain3",
    )


def beam_element(EI: float, rhoA: float, le: float):
    """Euler-Bernoulli element matrices for (v1, t1, v2, t2), t = dv/dx."""
    k = (
        EI
        / le**3
        * np.array(
            [
                [12, 6 * le, -12, 6 * le],
                [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                [-12, -6 * le, 12, -6 * le],
                [6 * le, 2 * le**2, -6 * le, 4 * le**2],
            ]
        )
    )
    m = (
        rhoA
        * le
        / 420
        * np.array(
            [
                [156, 22 * le, 54, -13 * le],
                [22 * le, 4 * le**2, 13 * le, -3 * le**2],
                [54, 13 * le, 156, -22 * le],
                [-13 * le, -3 * le**2, -22 * le, 4 * le**2],
            ]
        )
    )
    return k, m


def cantilever_modes() -> ModeSet:
    """The first modes of the clamped bar, bending in y and z."""
    p = CANTILEVER
    ne, le, area = p["elements"], p["L"] / p["elements"], p["b"] * p["h"]
    Iz, Iy = p["h"] * p["b"] ** 3 / 12, p["b"] * p["h"] ** 3 / 12
    nn = ne + 1
    # global DOFs per node: v (y), dv/dx (= rz), w (z), dw/dx (= -ry)
    K, M = np.zeros((4 * nn, 4 * nn)), np.zeros((4 * nn, 4 * nn))
    for e in range(ne):
        for plane, inertia in ((0, Iz), (2, Iy)):
            ke, me = beam_element(p["E"] * inertia, p["rho"] * area, le)
            idx = [4 * e + plane, 4 * e + plane + 1, 4 * (e + 1) + plane, 4 * (e + 1) + plane + 1]
            K[np.ix_(idx, idx)] += ke
            M[np.ix_(idx, idx)] += me
    free = slice(4, None)  # node 1 clamped
    # rows of w's slope dw/dx are -ry: flip their sign so every row is an x3dpd component
    T = np.diag(np.tile([1.0, 1.0, 1.0, -1.0], nn))[free, free]
    K, M = T @ K[free, free] @ T, T @ M[free, free] @ T
    nodes = np.repeat(np.arange(2, nn + 1), 4)
    dofs = np.tile(["y", "rz", "z", "ry"], nn - 1)
    return modes_from_matrices(
        K, M, nodes, dofs, n_modes=p["modes"], units=("in", "lbf", "s"), name="cantilever"
    )


def with_all_nodes(modes: ModeSet, node_ids) -> tuple[np.ndarray, np.ndarray]:
    """(node ids, shapes) over ``node_ids`` with all six components, 0 where ``modes`` has none
    (constrained components and nodes, as a finite-element code writes them)."""
    node_ids = np.asarray(node_ids)
    shapes = np.zeros((modes.n_modes, len(node_ids), 6))
    cols = np.searchsorted(node_ids, modes.node_ids)
    shapes[:, cols] = np.nan_to_num(modes.shapes, nan=0.0)
    return node_ids, shapes


def write_op2(path: Path, modes: ModeSet, node_ids, tables=("LAMA", "OUGV1")) -> None:
    """An OP2 with LAMA and OUGV1 (table code 7), 32-bit, written with pyNastran's writers
    (``tables`` leaves one out, for the tests of files without it)."""
    with numpy_in1d_for_import():
        from pyNastran.op2.op2 import OP2
        from pyNastran.op2.tables.lama_eigenvalues.lama_objects import RealEigenvalues
        from pyNastran.op2.tables.oug.oug_eigenvectors import RealEigenvectorArray
        from pyNastran.op2.writer.op2_writer import write_op2_header
    from cpylog import SimpleLogger

    node_ids, shapes = with_all_nodes(modes, node_ids)
    omega = 2 * np.pi * modes.freq_hz
    model = OP2(log=SimpleLogger(level="critical"), debug=None)
    model.set_as_msc()
    model.date = OP2_DATE
    grid = np.column_stack([node_ids, np.ones(len(node_ids), dtype=int)])
    vectors = RealEigenvectorArray.add_modal_case(
        "OUGV1",
        grid,
        shapes.astype(np.float32),
        1,
        modes.mode_numbers,
        omega**2,
        modes.freq_hz,
        is_sort1=True,
        title=path.stem.upper(),
        label="NORMAL MODES",
    )
    vectors.table_code = vectors.data_code["table_code"] = 7  # eigenvector, not displacement
    lama = RealEigenvalues(path.stem.upper(), "LAMA", modes.n_modes)
    lama.mode[:] = lama.extraction_order[:] = modes.mode_numbers
    lama.eigenvalues[:], lama.radians[:], lama.cycles[:] = omega**2, omega, modes.freq_hz
    lama.generalized_mass[:], lama.generalized_stiffness[:] = 1.0, omega**2
    s3, s9 = Struct(b"<3i"), Struct(b"<9i")
    with open(path, "wb") as f:
        write_op2_header(model, f, io.StringIO(), s3, post=-1, endian=b"<")
        for table in [t for t in (lama, vectors) if t.table_name in tables]:
            itable = table.write_op2(
                f, io.StringIO(), -1, True, model.date, is_mag_phase=False, endian=b"<"
            )
            f.write(s9.pack(4, itable, 4, 4, 1, 4, 4, 0, 4))  # end of the table's last record
            f.write(s3.pack(4, 0, 4))  # end of the table
        f.write(s3.pack(4, 0, 4))  # end of the file


def write_uff(path: Path, modes: ModeSet, node_ids, ndv: int, units_code: int, damping=None):
    """Dataset 164 then one dataset 55 (normal mode) per mode, ``ndv`` values per node."""
    import pyuff
    from pyuff.datasets.dataset_55 import prepare_55
    from pyuff.datasets.dataset_164 import prepare_164

    node_ids, shapes = with_all_nodes(modes, node_ids)
    length, force = {1: (1.0, 1.0), 7: (1 / 0.0254, 1 / 4.4482216152605)}[units_code]
    sets = [
        prepare_164(
            units_code=units_code,
            units_description=" ".join(modes.units),
            temp_mode=1,
            length=length,
            force=force,
            temp=1.0,
            temp_offset=273.15,
        )
    ]
    for r, mode in enumerate(modes.mode_numbers):
        values = {f"r{c + 1}": shapes[r, :, c] for c in range(ndv)}
        sets.append(
            prepare_55(
                id1=f"{path.stem} mode {mode}",
                model_type=1,
                analysis_type=2,
                data_ch=2 if ndv == 3 else 3,
                spec_data_type=8,
                data_type=2,
                n_data_per_node=ndv,
                node_nums=node_ids,
                load_case=1,
                mode_n=int(mode),
                freq=float(modes.freq_hz[r]),
                modal_m=1.0,
                modal_damp_vis=0.0 if damping is None else float(damping[r]),
                modal_damp_his=0.0,
                **values,
            )
        )
    if path.exists():
        path.unlink()
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "tests" / "fixtures" / "modes")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    chain, beam = chain_modes(), cantilever_modes()
    beam_nodes = np.arange(1, CANTILEVER["elements"] + 2)
    write_op2(args.out / "chain3.op2", chain, CHAIN["nodes"])
    write_uff(args.out / "chain3.uff", chain, CHAIN["nodes"], 3, 1, damping=CHAIN["damping"])
    write_modes_csv(args.out / "chain3.csv", chain)
    write_op2(args.out / "cantilever.op2", beam, beam_nodes)
    write_uff(args.out / "cantilever.uff", beam, beam_nodes, 6, 7)
    for ms in (chain, beam):
        print(f"{ms.path}: f = {', '.join(f'{f:.6g}' for f in ms.freq_hz)} Hz")
    return 0


if __name__ == "__main__":
    sys.exit(main())
