"""The kernel cache, for ``x3dpd cache`` (re-exports; docs/running.md, "The kernel cache"):

* :func:`cache_root` -- where it is (``$X3DPD_CACHE_DIR``, default ``~/.cache/x3dpd``);
* :func:`list_cache` -> :class:`CacheListing` -- its compiled step-loop variants with their
  manifest entries (effects, compile seconds, first user) and sizes on disk, numba's cache of
  the shared kernels beside x3dpd's sources;
* :func:`clear_cache` -- delete the compiled variants (all, or those of other sources);
* :class:`CacheError` -- a missing or unreadable cache (an :class:`~x3dpd.InputError`).
"""

from __future__ import annotations

from x3dpd.solver.cache_listing import (
    CacheListing,
    SourceFolder,
    VariantRow,
    clear_cache,
    list_cache,
)
from x3dpd.solver.kernel_cache import CacheError
from x3dpd.solver.variants import cache_root

__all__ = [
    "CacheError",
    "CacheListing",
    "SourceFolder",
    "VariantRow",
    "cache_root",
    "clear_cache",
    "list_cache",
]
