"""Work done in threads comes back to a served session through its event loop only (``app.runs.call_in_session``).

A Bokeh document is not thread-safe: ``doc.add_next_tick_callback`` called from the curve or solver threads raced the
event loop's own holds of the document, and a session's callbacks were then never run (its coupled limit curve stayed
at "computing… N of 5 amplitudes": 6 of 18 pages, 6 at once beside a busy core, before; 0 of 36 after,
``benchmarks/session_callbacks.py``). These tests pin the contract: the document is touched in the loop's thread."""

from __future__ import annotations

import ast
import asyncio
import threading
from pathlib import Path

from tornado import ioloop

from app import runs

ROOT = Path(__file__).resolve().parents[1]


class _Doc:
    """A document that records the thread each next-tick callback was added from (and runs it there)."""

    def __init__(self):
        self.added_in, self.ran = [], threading.Event()

    def add_next_tick_callback(self, fn):
        self.added_in.append(threading.get_ident())
        fn()
        self.ran.set()


def _loop_in_thread():
    """A tornado IOLoop running in a thread of its own, like the server's: (loop, its thread id, stop)."""
    ready, box = threading.Event(), {}

    def run():
        asyncio.set_event_loop(asyncio.new_event_loop())
        box["loop"], box["ident"] = ioloop.IOLoop.current(), threading.get_ident()
        ready.set()
        box["loop"].start()

    thread = threading.Thread(target=run, name="test-loop", daemon=True)
    thread.start()
    assert ready.wait(10)

    def stop():
        box["loop"].add_callback(box["loop"].stop)
        thread.join(10)

    return box["loop"], box["ident"], stop


def test_a_callback_from_another_thread_is_added_to_the_document_in_the_loops_thread():
    loop, loop_thread, stop = _loop_in_thread()
    try:
        doc, seen = _Doc(), []
        worker = threading.Thread(target=lambda: runs.call_in_session(doc, loop, lambda: seen.append(1)))
        worker.start()
        worker.join(10)
        assert doc.ran.wait(10)
        assert doc.added_in == [loop_thread] and seen == [1]
        assert worker.ident not in doc.added_in
    finally:
        stop()


def test_in_the_loops_own_thread_it_is_added_at_once():
    loop, loop_thread, stop = _loop_in_thread()
    try:
        doc, seen = _Doc(), []
        done = threading.Event()

        def on_loop():  # a callback of the loop itself: no second hop
            assert runs.session_loop() is loop
            runs.call_in_session(doc, loop, lambda: seen.append(1))
            done.set()

        loop.add_callback(on_loop)
        assert done.wait(10) and doc.added_in == [loop_thread] and seen == [1]
    finally:
        stop()


def test_a_session_that_ended_drops_the_callback_quietly():
    class Ended:
        def add_next_tick_callback(self, fn):
            raise RuntimeError("the session was destroyed")

    runs.call_in_session(Ended(), None, lambda: None)  # no loop: here, and the error is logged, not raised


def test_no_app_module_adds_a_next_tick_callback_but_call_in_session():
    """Every way back from a thread to a session goes through :func:`app.runs.call_in_session` (a next-tick
    callback added anywhere else could be added from a thread again)."""
    found = []
    for path in sorted((ROOT / "app").glob("*.py")):
        tree = ast.parse(path.read_text(), str(path))
        members = [m for node in tree.body for m in (node.body if isinstance(node, ast.ClassDef) else [node])]
        for fn in members:  # module functions and methods, each with what it nests
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found += [(path.name, fn.name) for node in ast.walk(fn)
                          if isinstance(node, ast.Attribute) and node.attr == "add_next_tick_callback"]
    assert found == [("runs.py", "call_in_session")], found
