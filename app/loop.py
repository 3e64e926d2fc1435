"""Session builds take turns with the rest of the server's event loop.

Loaded by the server plugin (:mod:`app.health`); nothing here runs at import.
"""

from __future__ import annotations

import asyncio

__all__ = ["take_turns", "in_turns"]


def take_turns() -> bool:
    """Let the event loop serve what waits between two sessions' builds (once per process; True if installed).

    Bokeh builds a session's document synchronously on the event loop, right
    after awaiting the application's ``on_session_created``. When many pages
    are requested at once, every build is ready in the same turn of the loop
    and they run back to back: the loop answered nothing else (``/liveness``,
    the open sessions' slider updates) for 44-53 s while 60 sessions opened
    (``benchmarks/loadtest.py``). Here the builds take a lock, released on
    the loop's next turn after the build (``call_soon`` from the hook, which
    runs once the synchronous build has returned), so whatever arrived
    meanwhile runs between two builds. The builds are not slower: one loop
    runs them one at a time either way.
    """
    from panel.io.application import Application

    if getattr(Application.on_session_created, "_takes_turns", False):
        return False
    Application.on_session_created = in_turns(Application.on_session_created)
    return True


def in_turns(hook):
    """``hook`` (a coroutine function) made to take a lock, released on the event loop's turn after it returns."""
    lock = None  # made in the loop, on the first session

    async def wrapped(*args, **kwargs):
        nonlocal lock
        if lock is None:
            lock = asyncio.Lock()
        await lock.acquire()
        try:
            return await hook(*args, **kwargs)
        finally:
            asyncio.get_running_loop().call_soon(lock.release)  # after the build that follows the hook

    wrapped._takes_turns = True
    return wrapped
