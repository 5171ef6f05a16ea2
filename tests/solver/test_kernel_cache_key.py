"""The kernel cache can never return stale machine code.

The cache folder's name hashes :func:`x3dpd.solver.variants.kernel_sources`; a source file the
compiled loop is built from but that the hash misses would let an edit of it reuse old machine
code silently. The variant's header and cache name are generated from its fields, so a field
that changes neither would share a cache entry with a different loop.
"""

from __future__ import annotations

import dataclasses
import inspect
from pathlib import Path

import pytest
from factories import BOX_LOOP
from numba.core.registry import CPUDispatcher

from x3dpd.solver import variants
from x3dpd.solver.variants import Variant, kernel_sources, make_advance

PACKAGE = Path(variants.__file__).resolve().parents[1]


def _sources_used(module) -> set[Path]:
    """x3dpd files of every compiled function reachable from ``module``'s globals (following
    each function's own globals), plus the files of the modules it names."""
    files: set[Path] = set()
    seen: set[int] = set()
    todo = [module.__dict__]
    while todo:
        names = todo.pop()
        for value in list(names.values()):
            if id(value) in seen:
                continue
            seen.add(id(value))
            if isinstance(value, CPUDispatcher):
                fn = value.py_func
                files.add(Path(inspect.getsourcefile(fn)).resolve())
                todo.append(fn.__globals__)
            elif inspect.isclass(value) and value.__module__.startswith("x3dpd"):
                files.add(Path(inspect.getsourcefile(value)).resolve())
    return {f for f in files if PACKAGE in f.parents}


def _missing(module, hashed) -> set[Path]:
    """Files the loop is built from that ``hashed`` leaves out (the generated variant file stands
    for the template)."""
    template = Path(variants._TEMPLATE).resolve()

    def source_of(f: Path) -> Path:  # a generated file stands for its template file
        if not f.name.startswith("advance_"):
            return f
        part = f.stem.partition("__")[2]
        return template.with_name(f"_template_{part}.py") if part else template

    return {source_of(f) for f in _sources_used(module)} - set(hashed)


def test_every_kernel_source_is_hashed():
    variant = Variant(
        springs=True,
        rigid=True,
        rigid_rotation=True,
        walls=True,
        pairs=True,
        friction=True,
        viscoelastic=True,
        external=True,
        motion=True,
        n_maxwell=2,
        axial_springs=True,
        rotational_springs=True,
    )
    module = make_advance(variant)
    hashed = kernel_sources()
    assert not _missing(module, hashed), "kernel sources left out of the cache key"
    # the check can fail: drop a source the loop really uses
    used = _sources_used(module)
    faces = PACKAGE / "geometry" / "faces.py"
    assert faces in used
    assert _missing(module, [p for p in hashed if p != faces]) == {faces}


def test_every_variant_field_changes_the_header_and_the_name():
    base = Variant()
    for f in dataclasses.fields(Variant):
        value = getattr(base, f.name)
        if isinstance(value, bool):
            other = not value
        elif isinstance(value, int):
            other = value + 2
        else:
            continue  # laws: see the registry test below
        changed = dataclasses.replace(base, **{f.name: other})
        assert changed.name() != base.name(), f.name
        assert changed.header() != base.header(), f.name


def test_every_registered_law_is_a_variant():
    for f in dataclasses.fields(Variant):
        if f.name not in variants._LAWS:
            continue
        registry, _ = variants._LAWS[f.name]
        names = {dataclasses.replace(Variant(), **{f.name: law}).name() for law in registry}
        headers = {dataclasses.replace(Variant(), **{f.name: law}).header() for law in registry}
        assert len(names) == len(headers) == len(registry)


def test_the_packed_entry_unpacks_bundles_in_advance_order():
    """``advance_packed`` unpacks plain tuples in ADVANCE_BUNDLES order: its unpacking line
    must name the bundles in that order."""
    import re

    from x3dpd.solver.bundles import ADVANCE_BUNDLES

    module = make_advance(Variant(walls=True, pairs=True))
    source = inspect.getsource(module.advance_packed.py_func)
    unpacked = re.search(r"\(([^)]*)\) = packed", source).group(1)
    assert [n.strip().rstrip("_") for n in unpacked.split(",")] == list(ADVANCE_BUNDLES)


def test_the_source_hash_is_kept_until_a_source_file_changes(monkeypatch, tmp_path):
    """The cache key is computed once per process while the sources are unchanged, and anew
    when a source file's modification time or size changes (here: a copy of the stamps list
    pointing at a scratch file standing in for one source)."""
    from x3dpd.solver import variants

    first = variants._source_hash()
    assert variants._source_hash() == first
    walked = []
    real = variants.kernel_sources
    monkeypatch.setattr(variants, "kernel_sources", lambda: walked.append(1) or real())
    assert variants._source_hash() == first and not walked  # kept: nothing re-walked
    stamps, digest = variants._HASHED
    fake = tmp_path / "source.py"
    fake.write_text("x = 1\n")
    st = fake.stat()
    monkeypatch.setattr(
        variants, "_HASHED", [stamps + ((fake, st.st_mtime_ns, st.st_size),), digest]
    )
    fake.write_text("x = 12\n")  # an edit: another size
    assert variants._source_hash() == first and walked == [1]  # re-walked, same real sources


@pytest.mark.rides(BOX_LOOP)
def test_a_frictionless_scene_compiles_one_loop_whatever_the_tangential_law():
    """Every PCOF 0 and no rolling law: no tangential law runs, so --friction must not make a
    loop of its own to compile (it did: one per law, in a suite of decks and options); a scene
    with friction keeps its law's loop. Run through x3dpd.run: the same trace bytes too."""
    import x3dpd
    from factories import floor_deck
    from x3dpd.model.build import build_model
    from x3dpd.solver.simulation import Simulation

    bare = floor_deck(dt=5e-7, mu=0.0)
    loops = {
        Simulation(build_model(bare), friction=law).variant
        for law in ("regularized", "coulomb", "mindlin", "linear_history")
    }
    assert len(loops) == 1
    rough = floor_deck(dt=5e-7, mu=0.3)
    loops = {
        Simulation(build_model(rough), friction=law).variant.friction_law
        for law in ("regularized", "mindlin")
    }
    assert loops == {"regularized", "mindlin"}
    a, b = (x3dpd.run(bare, tmax=4e-5, friction=law) for law in ("regularized", "mindlin"))
    assert a.trace.velocity.tobytes() == b.trace.velocity.tobytes()
    assert a.energy["residual"].tobytes() == b.energy["residual"].tobytes()
