"""x3dpd: an X3D-compatible explicit solver for particle impact dampers.

The package is layered; imports only go downward:
``cli`` -> ``deck`` | ``model`` | ``solver`` | ``io`` | ``analysis`` -> ``physics`` | ``geometry``.
"""

__version__ = "0.1.0"
