"""``x3dpd plot TRACE -o PNG``: time histories, the energy ledger and the particles' kinetic
energy of a run."""

from __future__ import annotations

import os

import click

from x3dpd.api.figures import DOF_NAMES, QUANTITIES, collect, plot_trace
from x3dpd.api.traces import iter_blocks
from x3dpd.cli._trace_scene import DECK_HELP, load_scene
from x3dpd.cli.outputs import refuse_existing
from x3dpd.errors import InputError


def _dof(text: str) -> int:
    t = text.strip().lower()
    if t in DOF_NAMES:
        return DOF_NAMES.index(t)
    if t.isdigit() and 1 <= int(t) <= 6:
        return int(t) - 1
    raise InputError(f"--dof {text!r}: expected 1..6 or one of {', '.join(DOF_NAMES)}")


@click.command("plot")
@click.argument("trace", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, metavar="PNG", help="Output image.")
@click.option(
    "--node",
    "nodes",
    multiple=True,
    type=int,
    metavar="ID",
    help="Traced node to plot (repeatable; default the first traced node).",
)
@click.option(
    "--dof",
    "dofs",
    multiple=True,
    metavar="DOF",
    help="DOF of each node: 1..6 or x, y, z, rx, ry, rz (repeatable; default x).",
)
@click.option(
    "--quantity",
    "quantities",
    multiple=True,
    type=click.Choice(QUANTITIES),
    help="Quantity to plot (repeatable; default displacement).",
)
@click.option(
    "--energy",
    "energy_path",
    default=None,
    metavar="CSV",
    help="The run's energy file (default: the one the sidecar records).",
)
@click.option(
    "--every",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Use every N-th output time.",
)
@click.option("--deck", default=None, metavar="DECK", help=DECK_HELP)
@click.option("--overwrite", is_flag=True, help="Replace an existing PNG.")
def plot(trace, output, nodes, dofs, quantities, energy_path, every, deck, overwrite) -> None:
    """Plot node histories, the energy ledger and the particles' kinetic energy of TRACE."""
    refuse_existing([output], overwrite)
    info, _, scene = load_scene(trace, deck)
    ids = [int(i) for i in info.node_ids]
    nodes = list(nodes) or [ids[0]]
    dof_idx = [_dof(d) for d in dofs] or [0]
    if len(dof_idx) == 1:
        dof_idx *= len(nodes)
    if len(nodes) == 1 and len(dof_idx) > 1:
        nodes *= len(dof_idx)
    if len(dof_idx) != len(nodes):
        raise InputError(
            f"give one --dof, or one per --node ({len(nodes)} nodes, {len(dof_idx)} dofs)"
        )
    picks, labels = [], []
    for nid, d in zip(nodes, dof_idx):
        if nid not in ids:
            raise InputError(
                f"node {nid} is not traced in {trace} (traced: "
                f"{', '.join(map(str, ids[:8]))}{', ...' if len(ids) > 8 else ''})"
            )
        picks.append((ids.index(nid), d))
        labels.append(f"node {nid} {DOF_NAMES[d]}")
    quantities = list(quantities) or ["displacement"]
    if "displacement" in quantities and any(d >= 3 for _, d in picks):
        raise InputError(
            "a trace keeps no rotation angles: plot rotational DOFs as velocity or acceleration"
        )
    energy = None
    path = energy_path or info.meta.get("energy_file")
    if path and not os.path.isfile(path):
        alt = os.path.join(os.path.dirname(os.path.abspath(trace)), os.path.basename(path))
        path = alt if os.path.isfile(alt) else (None if not energy_path else path)
    if path:
        from x3dpd.api.traces import read_energy

        energy = read_energy(path)
    hist = collect(iter_blocks(trace, len(ids), every=every), scene, picks)
    plot_trace(output, hist, labels, quantities, scene.units, energy, scene.title)
    click.echo(
        f"x3dpd: {trace} -> {output} ({hist.times.shape[0]} output times"
        f"{', energy ledger ' + path if path else ''})"
    )
