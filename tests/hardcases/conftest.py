"""Hard cases: scenes at the edge of what the solver resolves (docs/hardcases.md)."""
