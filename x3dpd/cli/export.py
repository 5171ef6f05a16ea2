"""``x3dpd export TRACE --vtk DIR | --lammps FILE``: the run for ParaView or OVITO."""

from __future__ import annotations

import os

import click

from x3dpd.api.figures import write_lammps_dump, write_vtk_series
from x3dpd.api.traces import iter_blocks
from x3dpd.cli._trace_scene import DECK_HELP, load_scene
from x3dpd.cli.outputs import refuse_existing
from x3dpd.errors import InputError


@click.command("export")
@click.argument("trace", type=click.Path(dir_okay=False))
@click.option(
    "--vtk",
    "vtk_dir",
    default=None,
    metavar="DIR",
    help="Write DIR/run.pvd with particles_*.vtu and cavity_*.vtu (ParaView).",
)
@click.option(
    "--lammps",
    "lammps",
    default=None,
    metavar="FILE",
    help="Write a LAMMPS-style text dump of the particles (OVITO).",
)
@click.option(
    "--every",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Export every N-th output time.",
)
@click.option("--from", "t_from", type=float, default=None, metavar="T", help="Start time [s].")
@click.option("--to", "t_to", type=float, default=None, metavar="T", help="End time [s].")
@click.option("--deck", default=None, metavar="DECK", help=DECK_HELP)
@click.option("--overwrite", is_flag=True, help="Replace an existing export.")
def export(trace, vtk_dir, lammps, every, t_from, t_to, deck, overwrite) -> None:
    """Export TRACE as a VTK time series (--vtk) and/or a LAMMPS dump (--lammps)."""
    if not vtk_dir and not lammps:
        raise InputError("export needs --vtk DIR or --lammps FILE (or both)")
    if vtk_dir and os.path.exists(os.path.join(vtk_dir, "run.pvd")) and not overwrite:
        raise InputError(f"{vtk_dir} already holds an export (run.pvd); pass --overwrite")
    if vtk_dir and os.path.exists(vtk_dir) and not os.path.isdir(vtk_dir):
        raise InputError(f"--vtk {vtk_dir}: not a folder")
    if lammps:
        refuse_existing([lammps], overwrite)
    info, _, scene = load_scene(trace, deck)
    lo = t_from if t_from is not None else float("-inf")
    hi = t_to if t_to is not None else float("inf")

    def blocks():
        return iter_blocks(trace, info.node_ids.shape[0], every=every, t_from=lo, t_to=hi)

    if vtk_dir:
        n = write_vtk_series(vtk_dir, scene, blocks())
        click.echo(
            f"x3dpd: {trace} -> {os.path.join(vtk_dir, 'run.pvd')} ({n} output times, "
            f"{scene.particle_rows.shape[0]} particles, {scene.tri.shape[0]} triangles)"
        )
    if lammps:
        n = write_lammps_dump(lammps, scene, blocks())
        click.echo(f"x3dpd: {trace} -> {lammps} ({n} output times, LAMMPS dump)")
