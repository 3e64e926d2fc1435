"""One decorator for every numba kernel of :mod:`core`, cached on disk where that is possible.

numba caches compiled code next to the source (``__pycache__``), in
``NUMBA_CACHE_DIR`` or in the user's cache directory. On a read-only install
with none of these writable, ``njit(cache=True)`` raises ``RuntimeError: cannot
cache function ...: no locator available`` at import time; :func:`jit` then
compiles without an on-disk cache instead (slower first call, same code).

A run's first call of its kernels compiles them when the cache holds none for
this source (a fresh install, an edited module, a read-only install without
``NUMBA_CACHE_DIR``): minutes on a busy machine. :func:`announce_compile` says
so once per process, before the wait, as a warning of the ``core`` logger
(Python prints it on stderr when logging is not configured; an application
that configures logging gets it as a record).
"""

from __future__ import annotations

import logging

import numba as nb

__all__ = ["jit", "CACHING", "KERNELS", "announce_compile", "COMPILE_NOTE"]

_OPTIONS = dict(fastmath=True, nogil=True)
#: False once a kernel could not be cached (no writable cache location): later kernels skip the attempt.
CACHING = True
#: Every kernel made by :func:`jit`, by ``"module.name"`` (e.g. ``"core.solvers._pdas.march"``).
KERNELS: dict = {}
#: What :func:`announce_compile` says.
COMPILE_NOTE = ("compiling the solver (first run after an install only: numba compiles it once and caches it on "
                "disk; this can take a minute or more)")
log = logging.getLogger("core")
_ANNOUNCED = False
#: Kernels :func:`announce_compile` has looked at: it reads a kernel's on-disk index once per process (a kernel
#: called only from other kernels never gets a signature of its own, and reading its index costs ~0.6 ms a run).
_LOOKED_AT: set = set()


def jit(fn):
    """``numba.njit(cache=True, fastmath=True, nogil=True)``, without the cache where none can be written."""
    global CACHING
    dispatcher = None
    if CACHING:
        try:
            dispatcher = nb.njit(cache=True, **_OPTIONS)(fn)
        except RuntimeError as e:
            if "no locator available" not in str(e):
                raise
            CACHING = False
    if dispatcher is None:
        dispatcher = nb.njit(cache=False, **_OPTIONS)(fn)
    KERNELS[f"{fn.__module__}.{fn.__name__}"] = dispatcher
    return dispatcher


def _cached(dispatcher) -> bool:
    """Whether numba's on-disk cache holds compiled code of ``dispatcher`` for its current source."""
    try:  # numba's index of the function's cache; empty when missing or written for another version of the file
        return bool(dispatcher._cache._cache_file._load_index())
    except Exception:  # noqa: BLE001 - no cache (a read-only install) or another numba layout: it compiles
        return False


def announce_compile(*names: str) -> bool:
    """Say once per process that the first run compiles, if kernel ``names`` are neither compiled nor cached.

    Parameters
    ----------
    *names : str
        Keys of :data:`KERNELS` (``"core.solvers._pdas.march"``): the kernels the coming run needs first.

    Returns
    -------
    bool
        True if it was said now (a warning of the ``core`` logger, :data:`COMPILE_NOTE`).
    """
    global _ANNOUNCED
    if _ANNOUNCED:
        return False
    kernels = [KERNELS[n] for n in names if n in KERNELS and n not in _LOOKED_AT]
    _LOOKED_AT.update(names)  # cached or compiled now, it stays so: compiled by the run when it was neither
    if not any(not d.signatures and not _cached(d) for d in kernels):
        return False
    _ANNOUNCED = True
    log.warning(COMPILE_NOTE)
    return True
