"""The Dask cluster a sweep, a design or a study runs on when ``--scheduler ADDRESS`` names one
(docs/cluster.md): its client, and a refusal that names the address when nothing answers there.

:func:`check_scheduler` connects once and lets go; the tools call it before they write anything,
so that a mistyped address or a scheduler not yet started costs a one-line error and no output
folder (it used to cost a Dask traceback after 30 s, and a half-made folder).
:func:`connect_scheduler` is the client the run then uses, with the same refusal.
"""

from __future__ import annotations

from x3dpd.errors import InputError

#: seconds to wait for a scheduler to answer
CONNECT_TIMEOUT = 10.0


def connect_scheduler(address: str, timeout: float | None = None):
    """A ``dask.distributed.Client`` of the scheduler at ``address``; an InputError naming it
    when none answers within ``timeout`` [s] (default :data:`CONNECT_TIMEOUT`)."""
    from dask.distributed import Client

    try:
        return Client(address, timeout=CONNECT_TIMEOUT if timeout is None else timeout)
    except (OSError, TimeoutError, ValueError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(
            f"--scheduler {address}: no Dask scheduler answers there ({reason}); start one with "
            "`dask scheduler` and its workers with `dask worker ADDRESS` (docs/cluster.md), or "
            "leave --scheduler out to run on this machine's cores"
        ) from None


def check_scheduler(address: str | None, timeout: float | None = None) -> None:
    """Connect to the scheduler at ``address`` and let go (nothing when ``address`` is None)."""
    if address is not None:
        connect_scheduler(address, timeout).close()
