"""x3dpd: an X3D-compatible explicit solver for particle impact dampers.

The public Python API (docs/python-api.md)::

    import x3dpd
    result = x3dpd.run("decks/beam_64.inp", tmax=0.05)
    result.trace.position        # (T, N, 3)
    result.energy["dissipated_friction"]

``run``, ``run_config`` (a run configured once: a ``RunConfig``), ``load_deck``, ``check``,
``build``, ``read_trace``, ``read_energy``, ``fit_time_step``, ``rules_of_thumb`` and the result
and error types are loaded on first use (importing ``x3dpd`` alone stays cheap).

The package is layered; imports only go downward: ``cli`` -> ``api`` -> ``deck`` | ``model`` |
``solver`` | ``io`` | ``analysis`` -> ``physics`` | ``geometry``.
"""

__version__ = "0.1.0"

__all__ = [
    "Chunk",
    "DeckError",
    "EnergyData",
    "FinalState",
    "FittedStep",
    "InputError",
    "RunConfig",
    "RunResult",
    "TraceData",
    "TraceError",
    "UnstableRunError",
    "X3dpdError",
    "build",
    "check",
    "fit_time_step",
    "load_deck",
    "read_energy",
    "read_trace",
    "rules_of_thumb",
    "run",
    "run_config",
]


def __getattr__(name: str):
    """Load the API lazily (PEP 562): ``x3dpd.run`` imports the solver on first use."""
    if name in __all__:
        from x3dpd import api

        return getattr(api, name)
    raise AttributeError(f"module 'x3dpd' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
