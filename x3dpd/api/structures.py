"""The structure as a linear system, for the tools above the API (re-exports; docs/design-guide.md):

* :class:`Model` -- the arrays a deck builds to (:func:`x3dpd.api.build`);
* :func:`linear_sdof` -> :class:`Sdof`, :func:`linear_modal` -> :class:`ModalLinear`,
  :func:`rigid_body` -- the structure a drive point sees, when it is linear: the closed forms
  of a sweep's undamped and added-mass baselines (x3dpd.model.linear_structure).
"""

from __future__ import annotations

from x3dpd.model.linear_structure import ModalLinear, Sdof, linear_modal, linear_sdof, rigid_body
from x3dpd.model.model import Model

__all__ = ["ModalLinear", "Model", "Sdof", "linear_modal", "linear_sdof", "rigid_body"]
