"""One decorator for every numba kernel of :mod:`core`, cached on disk where that is possible.

numba caches compiled code next to the source (``__pycache__``), in
``NUMBA_CACHE_DIR`` or in the user's cache directory. On a read-only install
with none of these writable, ``njit(cache=True)`` raises ``RuntimeError: cannot
cache function ...: no locator available`` at import time; :func:`jit` then
compiles without an on-disk cache instead (slower first call, same code).
"""

from __future__ import annotations

import numba as nb

__all__ = ["jit", "CACHING"]

_OPTIONS = dict(fastmath=True, nogil=True)
#: False once a kernel could not be cached (no writable cache location): later kernels skip the attempt.
CACHING = True


def jit(fn):
    """``numba.njit(cache=True, fastmath=True, nogil=True)``, without the cache where none can be written."""
    global CACHING
    if CACHING:
        try:
            return nb.njit(cache=True, **_OPTIONS)(fn)
        except RuntimeError as e:
            if "no locator available" not in str(e):
                raise
            CACHING = False
    return nb.njit(cache=False, **_OPTIONS)(fn)
