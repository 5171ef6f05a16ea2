"""Refusals before a run starts: particles that begin inside a wall (the report's printed
Appendix A deck) would blow the run up at its first step."""

from __future__ import annotations

from x3dpd.errors import InputError


def initial_penetration_error(model, limit: float, deck_path: str) -> InputError | None:
    """An :class:`InputError` naming the deepest particle that starts inside a wall deeper than
    ``limit`` x its radius (or behind a wall), None when there is none."""
    from x3dpd.model.check_geometry import particle_wall_penetrations, particles_outside

    if model.n_particles and model.shape_kind.shape[0]:
        err = _analytic_wall_error(model, limit, deck_path)
        if err is not None:
            return err
    if model.n_particles == 0 or model.tri_nodes.shape[0] == 0:
        return None
    r = model.radius
    found = []  # (depth / R, depth, node id, triangle, behind distance)
    for o in particles_outside(model):
        if o.triangle >= 0:  # centre behind a wall: the sphere is inside it by R + distance
            d = float(r[o.particle] + o.distance)
            found.append((d / r[o.particle], d, o.node_id, o.triangle, o.distance))
    behind = {f[2] for f in found}
    for p in particle_wall_penetrations(model, min_depth_fraction=limit):
        if p.node_id not in behind:
            found.append((p.depth / r[p.particle], p.depth, p.node_id, p.triangle, None))
    if not found:
        return None
    found.sort(key=lambda f: (-f[0], f[2]))
    rel, depth, nid, tri, behind_by = found[0]
    nodes = " ".join(str(int(model.node_ids[i])) for i in model.tri_nodes[tri])
    where = (
        f"; its centre is {behind_by:.6g} behind the wall, on the outside of the cavity"
        if behind_by is not None
        else ""
    )
    n = len({f[2] for f in found})
    others = (
        f" ({n} of the {model.n_particles} particles start inside a wall or behind it)"
        if n > 1
        else ""
    )
    return InputError(
        f"{deck_path}: particle node {nid} starts {depth:.6g} ({rel:.3g} R) deep in wall "
        f"triangle {tri + 1} (nodes {nodes}){where}, beyond the penetration limit "
        f"{limit:g} R{others}. The run would blow up at its first step: see "
        f"`x3dpd check {deck_path}`; decks/appendix_a_cube.inp is the repaired geometry of "
        f"the report's Appendix A deck."
    )


def _analytic_wall_error(model, limit: float, deck_path: str) -> InputError | None:
    """The deepest particle that starts outside its analytic wall (cylinder, capsule ...) or
    deeper than ``limit`` x its radius in it."""
    from x3dpd.model.check_shapes import describe_shape, shape_clearances

    r = model.radius
    bad = [f for f in shape_clearances(model) if not f.inside or -f.gap > limit * r[f.particle]]
    if not bad:
        return None
    f = min(bad, key=lambda f: (f.inside, f.gap))
    where = (
        "its centre lies outside it"
        if not f.inside
        else f"{-f.gap:.6g} ({-f.gap / r[f.particle]:.3g} R) deep in its wall"
    )
    return InputError(
        f"{deck_path}: particle node {f.node_id} starts in {describe_shape(model, f.shape)}"
        f" wrongly: {where}, beyond the penetration limit {limit:g} R. The run would blow up "
        f"at its first step: see `x3dpd check {deck_path}`."
    )
