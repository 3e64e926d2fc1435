"""Loading histories as data: schedules of the centre, the normal and the tangential load.

A layer of :mod:`core` (docs/dev/architecture.md): its modules import only from this layer and the layers below.
Importing the package imports none of them; ``core.loading.X`` after ``import core`` imports module X on first use.
"""


def __getattr__(name):
    """A module of this layer, imported on first use (PEP 562)."""
    import importlib
    import importlib.util

    if not name.startswith("__") and importlib.util.find_spec(f"{__name__}.{name}") is not None:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
