"""Session builds take turns with the rest of the server's event loop.

Loaded by the server plugin (:mod:`app.health`); nothing here runs at import.
"""

from __future__ import annotations

import asyncio

__all__ = ["take_turns", "in_turns", "GAP_S", "quiet_closed_sockets"]

#: Seconds the event loop serves other work (documents on their way, slider updates, ``/liveness``) between two
#: sessions' builds; a build takes about 0.5 s.
GAP_S = 0.05


def take_turns(after=None) -> bool:
    """Let the event loop serve what waits between two sessions' builds (once per process; True if installed).

    Bokeh builds a session's document synchronously on the event loop, right
    after awaiting the application's ``on_session_created``. When many pages
    are requested at once, every build is ready in the same turn of the loop
    and they run back to back: the loop answered nothing else (``/liveness``,
    the open sessions' slider updates) for 44-53 s while 60 sessions opened
    (``benchmarks/loadtest.py``). Here the builds take a lock, released on
    :data:`GAP_S` after the build (``call_later`` from the hook, which runs
    once the synchronous build has returned), so whatever arrived meanwhile
    runs between two builds. One turn of the loop was not enough: a page's
    document goes to the browser as some 250 awaited websocket writes, one
    per turn, so the pages opened together all got their documents when the
    last build was done (``benchmarks/loadtest.py``: ten pages opened at once
    were all up after 18.8 s). The builds are not slower: one loop runs them
    one at a time either way.

    ``after``, if given, is called after each build, before the lock is
    released (:meth:`app.heap.Heap.built`).
    """
    from panel.io.application import Application

    if getattr(Application.on_session_created, "_takes_turns", False):
        return False
    Application.on_session_created = in_turns(Application.on_session_created, after)
    return True


def in_turns(hook, after=None):
    """``hook`` (a coroutine function) made to take a lock, released :data:`GAP_S` after it returns (``after()``
    called first)."""
    lock = None  # made in the loop, on the first session

    def built():
        try:
            if after is not None:
                after()
        finally:
            lock.release()

    async def wrapped(*args, **kwargs):
        nonlocal lock
        if lock is None:
            lock = asyncio.Lock()
        await lock.acquire()
        try:
            return await hook(*args, **kwargs)
        finally:
            asyncio.get_running_loop().call_later(GAP_S, built)  # after the build that follows the hook

    wrapped._takes_turns = True
    return wrapped


def quiet_closed_sockets() -> bool:
    """Writes to a tab that has closed end quietly (once per process; True if installed).

    Panel sends a session's updates as one websocket write per message part
    (``panel.io.document.dispatch_tornado``: the header, the metadata, the
    content, each buffer) and awaits those writes later. When the tab closes
    while updates are on their way (the player playing, a solve's result
    arriving), a write raises ``WebSocketClosedError`` at once: the writes of
    the same message issued before it are then lost, never awaited, and when
    they fail asyncio logs "Task exception was never retrieved" with two
    tracebacks for each (7 in a class's session, issue 31). Here the parts are
    written one by one (as Panel 1.9 does), every write gets a done-callback
    that retrieves its outcome, and a write refused because the tab has gone
    ends the message (there is no one to send it to); a failure of another
    kind is still logged by Panel where it awaits the writes.
    """
    import json

    from panel.io import document
    from tornado.websocket import WebSocketClosedError, WebSocketHandler

    if getattr(document.dispatch_tornado, "_quiet", False):
        return False

    def retrieve(future) -> None:
        if not future.cancelled():
            future.exception()  # marks the outcome as seen: a closed tab is nothing to report

    def dispatch(conn, events=None, msg=None):
        socket = conn._socket
        ws_conn = getattr(socket, "ws_connection", False)
        if not ws_conn or ws_conn.is_closing():
            return []
        if msg is None:
            if not events:
                return []
            msg = conn.protocol.create("PATCH-DOC", events)
        parts = [(msg.header_json, False), (msg.metadata_json, False), (msg.content_json, False)]
        for buffer in msg._buffers:
            parts += [(json.dumps(buffer.ref), False), (buffer.to_bytes(), True)]
        futures = []
        for payload, binary in parts:
            try:
                future = WebSocketHandler.write_message(socket, payload, binary=binary)
            except WebSocketClosedError:
                break  # the tab has gone: the rest of the message has no one to go to
            future.add_done_callback(retrieve)
            futures.append(future)
        return futures

    dispatch._quiet = True
    document.dispatch_tornado = dispatch
    return True
