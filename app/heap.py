"""Sessions' objects set aside from the garbage collector's full passes; reclaimed once sessions have ended.

Loaded by the server plugin (:mod:`app.health`); nothing here runs at import.

A full pass of Python's cycle collector scans every object that is not
frozen and stops every thread, the event loop's too, for about 0.5 us an
object. A session's page is some 24 000 objects, alive as long as the
session: with 60 sessions open a full pass took 0.8-0.9 s, and under a
class's load (``benchmarks/loadtest.py``) the collector made one every few
seconds, inside whatever callback was running (longest callback 1.24 s,
with a pass of 0.83 s). Here:

* after each session's build the young generations are collected (the
  build's own cyclic garbage) and everything alive is frozen
  (:func:`gc.freeze`, a list splice): full passes then only scan what
  changed since the last page was built. Same load test: longest pass
  0.09 s, longest callback 0.40 s, and 504 solve round trips against 490;
* frozen objects are not collected, and a page's objects are cycles that
  the collector, not reference counting, frees when a session ends (of a
  page's 24 000, 2 800 went with the session's last reference). So once
  the sessions ended since the last reclaim are at least as many as those
  open (or none is open), the heap is unfrozen, collected and frozen again,
  in one pass: at most as much memory for ended sessions as for open ones,
  and a full pass once per so many ended sessions instead of every few
  seconds while a class works. That pass takes what a full pass takes:
  1.4 s after 60 sessions ended together (``tests/test_heap.py`` checks the
  objects are gone). About half of an ended page's objects survive one pass
  (the cause is not known; the second pass frees them): they go at the next
  reclaim, or a second later if no session is open.
"""

from __future__ import annotations

import gc
import threading
import time

__all__ = ["Heap", "HEAP", "set_aside_sessions"]

#: Seconds after a session ends before a due reclaim: Bokeh discards expired sessions in batches, one pass for all.
RECLAIM_DELAY_S = 1.0


class Heap:
    """The policy and its counts (one per server process, :data:`HEAP`)."""

    def __init__(self):
        self.open = self.ended = 0  # sessions built and not ended; ended since the last reclaim
        self.reclaims = self.reclaimed = 0  # reclaims, and objects the last one collected
        self.frozen = 0  # objects frozen after the start-up's freeze or the last reclaim (counting them is a scan)
        self.reclaim_max_s = 0.0
        self._due = False
        self._lock = threading.Lock()

    def built(self) -> None:
        """A session's page was built: collect the young generations and freeze what lives."""
        with self._lock:
            self.open += 1
        gc.collect(1)
        gc.freeze()

    def ending(self) -> bool:
        """A session ended; True if a reclaim is due (and not already scheduled): call :meth:`reclaim` soon."""
        with self._lock:
            self.open = max(0, self.open - 1)
            self.ended += 1
            if self._due or self.ended < max(1, self.open):
                return False
            self._due = True
            return True

    def reclaim(self) -> int:
        """Unfreeze, collect, freeze again; returns the number of objects collected.

        One pass: about half of an ended page's objects survive it (why is not known); they go at the next
        reclaim (a second pass here would double the pause).
        """
        t0 = time.perf_counter()
        gc.unfreeze()
        collected = gc.collect()
        gc.freeze()
        spent = time.perf_counter() - t0
        frozen = gc.get_freeze_count()  # a walk over every frozen object: tens of ms with a class open
        with self._lock:
            self._due, self.ended, self.frozen, self.reclaimed = False, 0, frozen, collected
            self.reclaims += 1
            self.reclaim_max_s = max(self.reclaim_max_s, spent)
        return collected

    def report(self) -> dict:
        """Counts for ``/liveness``: sessions open, reclaims, their longest pass [ms], the objects the last one
        collected and those frozen after it (or after the start-up's freeze)."""
        return {"sessions_open": self.open, "gc_reclaims": self.reclaims,
                "gc_reclaim_max_ms": round(1e3 * self.reclaim_max_s, 1), "gc_reclaimed": self.reclaimed,
                "gc_frozen": self.frozen}


HEAP = Heap()


def set_aside_sessions(heap: Heap = HEAP) -> bool:
    """Count the server's ended sessions and reclaim their objects when due (once per process; True if installed).

    The builds' side is :func:`app.loop.take_turns` (``after=heap.built``).
    """
    from panel.io.application import Application
    from tornado import ioloop

    if getattr(Application.on_session_destroyed, "_counted", False):
        return False
    destroyed = Application.on_session_destroyed

    def reclaim(follow_up=True):
        heap.reclaim()
        if follow_up and heap.open == 0:  # nobody there: what one pass left goes now, not at the next reclaim
            ioloop.IOLoop.current().call_later(RECLAIM_DELAY_S, lambda: heap.open == 0 and reclaim(False))

    async def on_session_destroyed(self, session_context):
        try:
            return await destroyed(self, session_context)
        finally:
            if heap.ending():
                ioloop.IOLoop.current().call_later(RECLAIM_DELAY_S, reclaim)

    on_session_destroyed._counted = True
    Application.on_session_destroyed = on_session_destroyed
    return True
