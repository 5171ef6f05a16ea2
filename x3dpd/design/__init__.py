"""Design tools over the Python API: steady-state frequency sweeps (``x3dpd sweep``), ring-down
damping (``x3dpd ringdown``) and their baselines (report Section 7.5; docs/design-guide.md)."""
