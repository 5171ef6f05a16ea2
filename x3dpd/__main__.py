"""``python -m x3dpd`` is the same as the ``x3dpd`` command."""

from x3dpd.cli import main

main()
