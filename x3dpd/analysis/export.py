"""Export a run for ParaView and OVITO (``x3dpd export``).

VTK (:func:`write_vtk_series`): one ``particles_NNNNNN.vtu`` (points, one VTK_VERTEX cell each,
point data ``radius`` [length], ``velocity`` [length/s] and ``spin`` [rad/s]) and one
``cavity_NNNNNN.vtu`` (the wall triangles, vertices placed with the cavity's master node) per
output time, written with meshio, and a ``run.pvd`` collection that gives each file its
simulated time. In ParaView: File > Open ``run.pvd``, then a Glyph filter (Sphere, scale by
``radius``, factor 2) shows the particles at their true size.

LAMMPS (:func:`write_lammps_dump`): a text dump in LAMMPS ``dump custom`` layout with columns
``id type x y z vx vy vz omegax omegay omegaz radius``, one ``ITEM: TIMESTEP`` section per output
time (the timestep is the output index; the simulated time is in ``ITEM: TIME``). OVITO reads
it directly (radius column -> particle radius).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from xml.sax.saxutils import quoteattr

import numpy as np

from x3dpd.analysis.scene import Scene


def _particles_mesh(scene: Scene, data: np.ndarray):
    import meshio

    p = data[scene.particle_rows]
    n = p.shape[0]
    return meshio.Mesh(
        np.ascontiguousarray(p[:, :3]),
        [("vertex", np.arange(n, dtype=np.int64)[:, None])],
        point_data={
            "radius": scene.radius.copy(),
            "velocity": np.ascontiguousarray(p[:, 3:6]),
            "spin": np.ascontiguousarray(p[:, 6:9]),
            "node_id": scene.node_ids[scene.particle_rows].astype(np.int64),
        },
    )


def _cavity_mesh(scene: Scene, data: np.ndarray):
    import meshio

    return meshio.Mesh(scene.vertices(data), [("triangle", scene.tri.copy())])


def write_vtk_series(
    folder: str | os.PathLike, scene: Scene, blocks: Iterable[tuple[float, np.ndarray]]
) -> int:
    """Write the VTK time series into ``folder`` (created if missing); return the frame count.

    Files are written one frame at a time; ``run.pvd`` is written last, so a folder with a
    ``run.pvd`` holds a complete export.
    """
    folder = os.fspath(folder)
    os.makedirs(folder, exist_ok=True)
    entries = []
    n = 0
    for t, data in blocks:
        for part, mesh in (
            ("particles", _particles_mesh(scene, data)),
            ("cavity", _cavity_mesh(scene, data)),
        ):
            if part == "cavity" and scene.tri.shape[0] == 0:
                continue
            name = f"{part}_{n:06d}.vtu"
            mesh.write(os.path.join(folder, name), file_format="vtu", binary=True)
            entries.append((t, part, name))
        n += 1
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
        "  <Collection>",
    ]
    for t, part, name in entries:
        part_no = 0 if part == "particles" else 1
        lines.append(
            f'    <DataSet timestep="{float(t)!r}" group="" part="{part_no}" '
            f"file={quoteattr(name)}/>"
        )
    lines += ["  </Collection>", "</VTKFile>", ""]
    with open(os.path.join(folder, "run.pvd"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines))
    return n


def write_lammps_dump(
    path: str | os.PathLike, scene: Scene, blocks: Iterable[tuple[float, np.ndarray]]
) -> int:
    """Write a LAMMPS-style text dump of the particles; return the frame count.

    The box bounds of each frame are the cavity's bounding box at that time (or the particles'
    when there are no walls).
    """
    n = 0
    ids = scene.node_ids[scene.particle_rows]
    with open(path, "w", encoding="ascii") as f:
        for t, data in blocks:
            p = data[scene.particle_rows]
            pts = scene.vertices(data) if scene.tri.shape[0] else p[:, :3]
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            f.write(
                f"ITEM: TIMESTEP\n{n}\nITEM: TIME\n{float(t)!r}\n"
                f"ITEM: NUMBER OF ATOMS\n{p.shape[0]}\n"
                "ITEM: BOX BOUNDS ff ff ff\n"
            )
            for a in range(3):
                # plain floats: a numpy scalar's repr is np.float64(...) on numpy 2
                f.write(f"{float(lo[a])!r} {float(hi[a])!r}\n")
            f.write("ITEM: ATOMS id type x y z vx vy vz omegax omegay omegaz radius\n")
            cols = np.column_stack([p[:, :9], scene.radius])
            for nid, row in zip(ids, cols):
                f.write(f"{int(nid)} 1 " + " ".join(f"{v:.10g}" for v in row) + "\n")
            n += 1
    return n


def read_lammps_dump(path: str | os.PathLike) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """Frames of a dump written by :func:`write_lammps_dump`: ``(time, ids, columns)`` with
    columns ``x y z vx vy vz omegax omegay omegaz radius`` (for checks and small files)."""
    frames = []
    with open(path, encoding="ascii") as f:
        lines = f.read().splitlines()
    k = 0
    while k < len(lines):
        assert lines[k] == "ITEM: TIMESTEP", lines[k]
        t = float(lines[k + 3])
        n = int(lines[k + 5])
        body = np.array([[float(v) for v in ln.split()] for ln in lines[k + 11 : k + 11 + n]])
        body = body.reshape(n, 12)
        frames.append((t, body[:, 0].astype(np.int64), body[:, 2:]))
        k += 11 + n
    return frames
