"""Movies of a run: the particles in their moving cavity (``x3dpd movie``; report Figure 44).

The report's ``pmov.m`` (Appendix E) draws the particles as circles projected on a plane, shaded
by depth. Done right here: the depth shading is normalised over the cavity's own extent along the
view axis (pmov.m assumes a cavity centred on z = 0 and overflows on the beam decks), the frame
count is unlimited (pmov.m's counter is int8), each frame shows the simulated time, and the
cavity's outline is drawn from the deck's triangles, moving with its master node
(:class:`x3dpd.analysis.scene.Scene`). Frames are streamed to the encoder one at a time
(imageio-ffmpeg: H.264 MP4 or GIF), so a 15 s trace needs no more memory than a short one.

Views: ``xy`` (looking along -z: x to the right, y up), ``xz``, ``yz``, ``zy``; the depth is the
remaining axis, nearer particles are lighter and drawn last.
"""

from __future__ import annotations

import os
from collections.abc import Iterable

import numpy as np

from x3dpd.analysis.scene import Scene
from x3dpd.errors import InputError

VIEWS = {"xy": (0, 1, 2), "xz": (0, 2, 1), "yz": (1, 2, 0), "zy": (2, 1, 0)}
FORMATS = (".mp4", ".gif", ".png")


def _figure(
    scene: Scene,
    view: str,
    size_px: tuple[int, int],
    lo: np.ndarray,
    hi: np.ndarray,
    dpi: int = 100,
):
    import matplotlib

    matplotlib.use("Agg", force=True)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import EllipseCollection, LineCollection
    from matplotlib.figure import Figure

    a, b, _ = VIEWS[view]
    fig = Figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.12, 0.1, 0.84, 0.8))
    pad = 0.08 * float(np.max(hi - lo) or 1.0)
    ax.set_xlim(lo[a] - pad, hi[a] + pad)
    ax.set_ylim(lo[b] - pad, hi[b] + pad)
    ax.set_aspect("equal", adjustable="box")
    length = scene.units.get("length", "")
    axis = "xyz"
    ax.set_xlabel(f"{axis[a]} [{length}]" if length else axis[a])
    ax.set_ylabel(f"{axis[b]} [{length}]" if length else axis[b])
    walls = LineCollection([], colors="0.25", linewidths=0.8, animated=True)
    ax.add_collection(walls)
    balls = EllipseCollection(
        widths=2 * scene.radius,
        heights=2 * scene.radius,
        angles=np.zeros_like(scene.radius),
        units="xy",
        offsets=np.zeros((scene.radius.shape[0], 2)),
        offset_transform=ax.transData,
        cmap="Blues_r",
        edgecolors="k",
        linewidths=0.3,
        animated=True,
    )
    balls.set_clim(0.0, 1.3)  # depth 0 (far) .. 1 (near): dark blue to light
    ax.add_collection(balls)
    label = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=9, animated=True)
    if scene.title:
        fig.suptitle(scene.title.splitlines()[0][:90], fontsize=8)
    fig.canvas.draw()  # the static parts once; frames draw the animated artists over them
    background = fig.canvas.copy_from_bbox(fig.bbox)
    return fig, walls, balls, label, background


def _draw(
    scene: Scene, view: str, parts, t: float, data: np.ndarray, depth_range: tuple[float, float]
) -> None:
    fig, walls, balls, label, background = parts
    a, b, c = VIEWS[view]
    v = scene.vertices(data)
    if scene.outline.shape[0]:
        walls.set_segments(v[scene.outline][..., [a, b]])
    p = data[scene.particle_rows, :3]
    lo, hi = depth_range
    depth = (p[:, c] - lo) / (hi - lo) if hi > lo else np.full(p.shape[0], 0.5)
    order = np.argsort(depth, kind="stable")  # far first, near drawn on top
    balls.set_offsets(p[order][:, [a, b]])
    balls.set_widths(2 * scene.radius[order])
    balls.set_heights(2 * scene.radius[order])
    balls.set_array(np.clip(depth[order], 0.0, 1.0))
    label.set_text(f"t = {t:.6g} {scene.units.get('time', 's')}")
    fig.canvas.restore_region(background)
    ax = walls.axes
    for artist in (walls, balls, label):
        ax.draw_artist(artist)


def _rgb(fig) -> np.ndarray:
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def write_movie(
    path: str | os.PathLike,
    scene: Scene,
    blocks: Iterable[tuple[float, np.ndarray]],
    *,
    view: str = "xy",
    fps: float = 25.0,
    size_px: tuple[int, int] = (768, 576),
) -> int:
    """Encode one frame per ``(time, data)`` block into ``path`` (.mp4 or .gif); return the count.

    ``.png`` writes the first block only (a still). Raises InputError for an unknown view or
    format, or when there is no block to draw.
    """
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise InputError(f"{path}: movie format must be one of {', '.join(FORMATS)}")
    if view not in VIEWS:
        raise InputError(f"view {view!r}: expected one of {', '.join(VIEWS)}")
    parts = None
    c = VIEWS[view][2]

    def start(data):
        """Figure and depth range framing the cavity and the particles of the first frame."""
        lo, hi = scene.bounds(data)
        return _figure(scene, view, size_px, lo, hi), (float(lo[c]), float(hi[c]))

    if ext == ".png":
        for t, data in blocks:
            parts, depth_range = start(data)
            _draw(scene, view, parts, t, data, depth_range)
            from PIL import Image

            Image.fromarray(_rgb(parts[0])).save(path)
            return 1
        raise InputError(f"{path}: the trace has no output time in the requested range")
    import imageio_ffmpeg

    writer = None
    n = 0
    try:
        for t, data in blocks:
            if parts is None:
                parts, depth_range = start(data)
            _draw(scene, view, parts, t, data, depth_range)
            frame = _rgb(parts[0])
            if writer is None:
                h, w = frame.shape[:2]
                if ext == ".gif":
                    writer = imageio_ffmpeg.write_frames(
                        path,
                        (w, h),
                        fps=fps,
                        codec="gif",
                        pix_fmt_out="rgb8",
                        macro_block_size=1,
                        output_params=["-loop", "0"],
                    )
                else:
                    writer = imageio_ffmpeg.write_frames(
                        path, (w, h), fps=fps, codec="libx264", macro_block_size=16
                    )
                writer.send(None)
            writer.send(frame)
            n += 1
    finally:
        if writer is not None:
            writer.close()
    if n == 0:
        raise InputError(f"{path}: the trace has no output time in the requested range")
    return n
