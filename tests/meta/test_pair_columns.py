"""The pair contacts' law loop (``_pair_response``) is vectorized: packed square roots and
divisions in its machine code, and no gather when every particle is alike (it then reads the
columns the filter gathered, contiguously). Checked by tools/bench/check_vector.py, which
compiles the loop afresh from a variant's generated source (a few seconds per variant); the
default suite checks the bench scene's viscoelastic variant and the law with the most history
(Hertz-Mindlin with rolling resistance), the validation suite every variant of the tool.
"""

from __future__ import annotations


import pytest

import check_vector  # tools/bench: on pytest's pythonpath (pyproject.toml)

DEFAULT = ("regularized_visco", "mindlin_rolling")


def _verdict(name: str, **kw) -> str:
    scene, friction, rolling, one_kind = check_vector.VARIANTS[name]
    asm = check_vector.response_asm(scene, friction, rolling, one_kind, **kw)
    return check_vector.verdict(check_vector.packed_instructions(asm), one_kind)


@pytest.mark.parametrize("name", DEFAULT)
def test_the_law_loop_is_packed(name):
    assert _verdict(name) == ""


@pytest.mark.validate
@pytest.mark.parametrize("name", [n for n in check_vector.VARIANTS if n not in DEFAULT])
def test_every_variant_of_the_law_loop_is_packed(name):
    assert _verdict(name) == ""


def test_the_check_flags_a_scalar_loop():
    # without noalias LLVM cannot tell the columns apart and keeps the loop scalar
    assert _verdict("regularized_visco", noalias=False).startswith("no packed")
