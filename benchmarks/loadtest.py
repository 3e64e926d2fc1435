"""Load test of the served explorer: many sessions driven through Bokeh's websocket protocol, not browsers.

Usage: python benchmarks/loadtest.py [--sessions 60] [--open-over 30] [--seconds 60] [--cluster 2]
       [--figures-in-view 1] [--json FILE]

Serves ``app/main.py`` and the yardstick page (``benchmarks/yardstick.py``: a
template, four sliders, two HoloViews plots) from one ``panel serve`` on
127.0.0.1, and drives sessions through Bokeh's websocket protocol, all of
them on one asyncio loop (one websocket per session, no browser). The
client opens a session as ``bokeh.client.pull_session`` does but never
builds Bokeh models: it keeps the document as JSON, applies the server's
PATCH-DOC events to it and sends slider moves as a browser does
(PATCH-DOC with a ModelChanged event for ``value`` while dragged, for
``value`` and then ``value_throttled`` on release). As a page opens, it
reports the sentinel of the figure a 1280x720 window shows as seen
(``--figures-in-view``, default 0: the first screen's figures come with the
page since issue 22), and waits for that figure: the server
draws the others only when a browser scrolls to them. Decoding the
document into Bokeh models (``bokeh.client``) cost a Python client 4-5 s of
CPU per session, more than the server spends building it, so that the load
generator, not the server, limited a 60-session run. What is
measured is what a session costs the server; the load generator's own CPU
time is printed beside the server's. With ``--cluster N`` the solves go to
a loopback Dask cluster of N workers (``dask scheduler`` and ``dask
worker`` processes started here; ``SHAKEDOWN_SCHEDULER`` for the server).

Phases, each printed:

1. CPU per session: ``--cpu-sessions`` sessions of the explorer opened one
   after another (each closed before the next), then as many of the
   yardstick; the server process's CPU time (``/proc/<pid>/stat``, all its
   threads) per session, and the ratio (goal: at most 2).
2. Burst: ``--burst`` sessions open at once while ``/liveness`` is polled
   every 0.25 s; its worst latency (goal: under 2 s).
3. Class: ``--sessions`` sessions open, evenly spread over ``--open-over``
   seconds; each then, until ``--seconds`` after the last opening, drags the
   ft slider (every third time the w slider) through three values (no
   release: the analytical layers follow, no solve) and releases that
   slider at a value no session has used (a new solve). The *solve round
   trip* runs from sending the release to the run card's text changing in
   the session's document.

Printed: errors (goal 0: a session that fails to open in 180 s, a round
trip over 60 s, an ERROR reply to a slider move, a failed or slow
``/liveness`` (over 30 s), a traceback or ERROR in the server's log), time
until all sessions are up, median and p95 of the round trips,
``/liveness`` latency, the longest time the server's event loop was
blocked and the longest single callback it ran (``SHAKEDOWN_LOOP_WATCH_MS``,
reported by ``/liveness``; goal: no callback over 0.5 s), the server's memory (VmRSS) before and after, and the CPU time
of the server and of the load generator (this process).

Every loop is bounded in count and in time.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import functools
import itertools
import json
import math
import os
import re
import signal
import statistics
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from app import limits  # noqa: E402
from app.runs import SOLVE_TASK  # noqa: E402
from app.serving import dask_cluster, served_app, tasks_done  # noqa: E402

YARDSTICK = Path(__file__).resolve().parent / "yardstick.py"
FT_TITLE = "ft = Ft/(μ Fn)"
W_TITLE = "w = W/a"
ROUND_TRIP_TIMEOUT_S = 60.0
OPEN_TIMEOUT_S = 180.0
LIVENESS_LIMIT_S = 30.0
MAX_ROUND_TRIPS_PER_SESSION = 500
#: Figure places a browser reports shown as the page opens, at 1280x720 (the others when scrolled to; measured by
#: tests/test_app_browser.py::test_figures_are_drawn_as_the_page_is_scrolled_to_them): none since issue 22, the
#: first screen's three figures come with the page
FIGURES_IN_VIEW = 0
_TICK = os.sysconf("SC_CLK_TCK")

_RECORD = re.compile(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d,\d{3} ", re.M)
# Bokeh/Tornado races when a client leaves mid-update: a write to the closed socket,
# or a patch that arrives after its session was detached. Not the app's errors.
_DISCONNECT = ("WebSocketClosedError", "assert self._session is not None", "Stream is closed")


def classify_server_log(log: str) -> tuple[list[str], list[str]]:
    """Split a server log into error records and disconnect noise; returns (errors, noise)."""
    starts = [m.start() for m in _RECORD.finditer(log)] + [len(log)]
    records = [log[a:b] for a, b in zip(starts[:-1], starts[1:])] or ([log] if log.strip() else [])
    errors, noise = [], []
    for rec in records:
        if "Traceback" not in rec and " ERROR " not in rec and "error handling message" not in rec:
            continue
        if any(sig in rec for sig in _DISCONNECT) and "/app/" not in rec and "/core/" not in rec:
            noise.append(rec)
        else:
            errors.append(rec)
    return errors, noise


def _cpu_s(pid: int) -> float:
    """CPU time (user + system) of process ``pid`` so far [s], all its threads."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICK


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def _percentile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, int(round(q * (len(v) - 1))))] if v else float("nan")


def _health(base: str, reset: bool = False, timeout: float = LIVENESS_LIMIT_S) -> dict:
    with urllib.request.urlopen(f"{base}/liveness" + ("?reset=1" if reset else ""), timeout=timeout) as r:  # noqa: S310
        return json.loads(r.read())


def _loop_ms(base: str, stats: dict, phase: str) -> None:
    """Since the last call (a new window starts): the longest the server's event loop was blocked, and the
    longest single callback it ran, and the garbage collector's longest pass [ms], into
    ``stats["loop_lag_<phase>_ms"]``, ``["loop_callback_<phase>_ms"]`` and ``["gc_<phase>_ms"]``; the watch's
    resolution (its interval, and how late its thread woke at most) into ``stats["loop_watch_interval_ms"]`` and
    ``["watch_late_<phase>_ms"]``."""
    lag = callback = collection = late = float("nan")
    health: dict = {}
    for attempt in range(3):  # the loop may still be busy with sessions that are being built
        try:
            health = _health(base, reset=True, timeout=120)
            lag, callback = health.get("loop_max_lag_ms", lag), health.get("loop_max_callback_ms", callback)
            collection, late = health.get("gc_max_ms", collection), health.get("watch_late_ms", late)
            stats["loop_watch_interval_ms"] = health.get("loop_watch_interval_ms", float("nan"))
            break
        except OSError as e:
            error = e
    else:
        stats["errors"].append(f"/liveness did not answer in 3 x 120 s: {type(error).__name__}")
    stats[f"loop_lag_{phase}_ms"], stats[f"loop_callback_{phase}_ms"] = lag, callback
    stats[f"gc_{phase}_ms"], stats[f"watch_late_{phase}_ms"] = collection, late
    if phase == "class":  # the heap's counts (app/heap.py): reclaims of ended sessions' objects so far
        stats["heap"] = {k: health.get(k) for k in ("sessions_open", "gc_reclaims", "gc_reclaim_max_ms")}


def _model_ids(value, register=None) -> set:
    """Ids of the models ``value`` (decoded JSON of Bokeh's protocol) refers to, not looking inside them.

    Bokeh 3 sends a model inline where a message first mentions it,
    ``{"type": "object", "name": ..., "id": ..., "attributes": {...}}``, and
    as a reference ``{"id": ...}`` afterwards. With ``register`` (a dict),
    every inline model met, nested ones too, is also put there as
    ``id -> {"id": id, "type": name, "attributes": {...}}``. Buffer references
    (``{"id": ...}`` of binary data) come out as ids too: no model has them.
    """
    ids: set = set()

    def walk(v, top):
        if isinstance(v, dict):
            if "id" in v and len(v) == 1:  # a reference
                if top:
                    ids.add(v["id"])
                return
            if v.get("type") == "object" and "id" in v:  # a model inline
                if top:
                    ids.add(v["id"])
                if register is None:
                    return
                register[v["id"]] = {"id": v["id"], "type": v.get("name"), "attributes": v.get("attributes", {})}
                top = False  # what an inline model holds belongs to it
            for x in v.values():
                walk(x, top)
        elif isinstance(v, list):
            for x in v:
                walk(x, top)

    walk(value, True)
    return ids


@functools.lru_cache(maxsize=None)
def _declares(type_name: str, prop: str) -> bool | None:
    """Whether Bokeh's model class ``type_name`` has property ``prop`` (None: a type not known here).

    The document's JSON leaves out properties at their defaults (a slider's
    ``value_throttled``), so the class says what a model has; only the
    class is looked at, no model is built.
    """
    import bokeh.models  # noqa: F401 - registers Bokeh's model classes by name
    from bokeh.model import Model

    cls = Model.model_class_reverse_map.get(type_name)
    return None if cls is None else prop in cls.properties()


class DocumentJSON:
    """A served document as plain JSON: its models by id, updated by the server's PATCH-DOC events.

    No Bokeh model is built (decoding the explorer's document into models
    costs a Python client 4-5 s of CPU, more than the server spends building
    it). Only models reachable from the roots count, as in a Bokeh
    document: a card replaced by a new model is found, the old one is not.

    Parameters
    ----------
    doc : dict
        The ``doc`` of a PULL-DOC-REPLY's content (``roots`` with the models inline).
    """

    def __init__(self, doc: dict):
        self.models: dict = {}
        self._children: dict = {}
        self._reachable: list | None = None
        self.roots = list(self._register(doc.get("roots", [])))

    def _register(self, value) -> set:
        """Put the models inline in ``value`` in the document; returns the ids of the models ``value`` refers to."""
        found: dict = {}
        ids = _model_ids(value, register=found)
        self.models.update(found)
        for model_id in found:  # a model sent again inline comes with all its attributes
            self._children.pop(model_id, None)
        return ids & self.models.keys()

    def children(self, model_id) -> set:
        """Ids of the models that model ``model_id``'s attributes refer to."""
        if model_id not in self._children:
            self._children[model_id] = _model_ids(self.models[model_id]["attributes"]) & self.models.keys()
        return self._children[model_id]

    def reachable(self) -> list:
        """The models reachable from the roots, as ``{"id", "type", "attributes"}`` dicts (cached until the
        document's structure changes)."""
        if self._reachable is None:
            seen, todo = set(), [r for r in self.roots if r in self.models]
            for _ in range(len(self.models) + 1):  # each model is expanded once
                if not todo:
                    break
                new = [c for m in todo if m not in seen for c in self.children(m)]
                seen.update(todo)
                todo = [m for m in new if m not in seen]
            self._reachable = [model for m, model in self.models.items() if m in seen]
        return self._reachable

    def apply_patch(self, content: dict) -> None:
        """Apply a PATCH-DOC's events: ``ModelChanged`` (new models in its value are registered),
        ``RootAdded`` and ``RootRemoved``; other kinds (column data, titles, messages) are ignored."""
        for event in content.get("events", []):
            kind = event.get("kind")
            if kind == "ModelChanged":
                model_id, attr, new = event["model"]["id"], event["attr"], event.get("new")
                if model_id not in self.models:
                    continue
                refs = self._register(new)
                attributes = self.models[model_id]["attributes"]
                structural = bool(refs) or bool(_model_ids(attributes.get(attr)) & self.models.keys())
                attributes[attr] = new
                if structural:
                    self._children.pop(model_id, None)
                    self._reachable = None
            elif kind == "RootAdded":
                self.roots += list(self._register(event.get("model")))
                self._reachable = None
            elif kind == "RootRemoved":
                gone = _model_ids(event.get("model"))
                self.roots = [r for r in self.roots if r not in gone]
                self._reachable = None

    def find(self, predicate) -> dict | None:
        """The first model (``{"id", "type", "attributes"}``) of the document for which ``predicate`` holds."""
        return next((m for m in self.reachable() if predicate(m)), None)

    def slider(self, title: str) -> dict | None:
        """The slider titled ``title`` (a model with a ``value_throttled`` property)."""
        def is_slider(m):
            a = m["attributes"]
            return a.get("title") == title and (_declares(m["type"], "value_throttled") or "value_throttled" in a)
        return self.find(is_slider)

    def run_card(self) -> dict | None:
        """The card that describes the run shown (its text names the steps and the elements)."""
        def is_card(m):
            text = m["attributes"].get("text")
            return isinstance(text, str) and " steps" in text and "el.," in text
        return self.find(is_card)


def model_changed(model_id: str, changes: dict):
    """A PATCH-DOC message with a ModelChanged event per item of ``changes`` (attribute -> new value, in order)
    for model ``model_id``: the JSON of ``bokeh.document.events.ModelChangedEvent.to_serializable``, in one
    message as BokehJS sends the properties set together by one ``setv``."""
    from bokeh.protocol.messages.patch_doc import patch_doc

    events = [{"kind": "ModelChanged", "model": {"id": model_id}, "attr": attr, "new": value}
              for attr, value in changes.items()]
    return patch_doc(patch_doc.create_header(), {}, {"events": events})


def document_ready():
    """The PATCH-DOC message BokehJS sends once it has rendered the page: a ``document_ready`` event
    (``bokeh.events.DocumentReady``, as ``MessageSentEvent.to_serializable`` writes it). Panel marks the
    session connected on it (``panel.io.state._on_load``)."""
    from bokeh.protocol.messages.patch_doc import patch_doc

    event = {"type": "event", "name": "document_ready", "values": {"type": "map", "entries": []}}
    events = [{"kind": "MessageSent", "msg_type": "bokeh_event", "msg_data": event}]
    return patch_doc(patch_doc.create_header(), {}, {"events": events})


class Session:
    """One session of a served page, driven through Bokeh's websocket protocol without Bokeh models.

    It opens the websocket as ``bokeh.client.pull_session`` does (a new
    session id, its JWT token as the subprotocol, the ``arguments`` in the
    query, which the app reads as the page's query), pulls the document as
    JSON (:class:`DocumentJSON`) and keeps it up to date with the server's
    PATCH-DOC messages in a task of its own; slider moves go out as the
    browser sends them. Messages are framed by Bokeh's own ``Protocol`` and
    ``Receiver``. Use :meth:`open`.
    """

    def __init__(self, socket, name: str, errors: list):
        from bokeh.client.websocket import WebSocketClientConnectionWrapper
        from bokeh.protocol import Protocol
        from bokeh.protocol.receiver import Receiver

        self.ws = socket
        self.socket = WebSocketClientConnectionWrapper(socket)  # the write lock Bokeh's messages take
        self.protocol = Protocol()
        self.receiver = Receiver(self.protocol)
        self.name, self.errors = name, errors
        self.doc: DocumentJSON | None = None
        self.closed = False
        self.sent = self.answered = 0
        self.changed = asyncio.Event()
        self._pull_id = None
        self._reader = None

    @classmethod
    async def open(cls, url: str, arguments: dict | None = None, name: str = "session",
                   errors: list | None = None, timeout: float = OPEN_TIMEOUT_S) -> Session:
        """Connect to ``url`` (an app's http URL), wait for the ACK and pull the document.

        ``errors`` receives a message per ERROR reply of the server. Raises on
        failure (TimeoutError when not open after ``timeout`` s,
        ConnectionError when the server closes the socket first).
        """
        from bokeh.util.strings import format_url_query_arguments
        from bokeh.util.token import generate_jwt_token, generate_session_id
        from tornado.httpclient import HTTPRequest
        from tornado.websocket import websocket_connect

        deadline = time.monotonic() + timeout
        ws_url = format_url_query_arguments(url.replace("http", "ws", 1).rstrip("/") + "/ws", arguments or {})
        request = HTTPRequest(ws_url, connect_timeout=timeout, request_timeout=timeout)
        token = generate_jwt_token(generate_session_id())
        socket = await asyncio.wait_for(websocket_connect(
            request, subprotocols=["bokeh", token], max_message_size=20 * 1024 * 1024), timeout)
        self = cls(socket, name, [] if errors is None else errors)
        try:
            await asyncio.wait_for(self._start(), max(0.0, deadline - time.monotonic()))
        except BaseException:
            await self.close()
            raise
        return self

    async def _start(self):
        ack = await self._message()
        if ack is None or ack.msgtype != "ACK":
            raise ConnectionError(f"expected ACK, got {ack and ack.msgtype}")
        request = self.protocol.create("PULL-DOC-REQ")
        self._pull_id = request.header["msgid"]
        await request.send(self.socket)
        self._reader = asyncio.create_task(self._read())
        if not await self.wait_until(lambda: self.doc is not None, OPEN_TIMEOUT_S):
            raise ConnectionError("the socket closed before the document came")
        # a browser says when it has rendered the page, and only then does Panel (1.9) count the session as
        # connected: before, it drops the model changes made under a hold (panel.io.document.hold), and it holds
        # the document around every browser event; a session that never said so was never sent the figure
        # drawn when its sentinel reported (the heap test's sessions waited 180 s for it)
        await document_ready().send(self.socket)
        self.sent += 1

    async def _message(self):
        """The next whole message from the server, or None when the socket closed."""
        for _ in range(10_000):  # fragments of one message: header, metadata, content and the buffers
            fragment = await self.socket.read_message()
            if fragment is None:
                return None
            message = await self.receiver.consume(fragment)
            if message is not None:
                return message
        raise ConnectionError("a message of over 10000 fragments")

    async def _read(self):
        """Handle the server's messages until the socket closes (as the Bokeh client: patches are applied,
        replies are counted, an ERROR is an error of the run; the server's websocket pings are answered by
        Tornado). The socket is given up after a patch that cannot be applied."""
        early: list = []  # patches not applied yet
        try:
            for _ in range(100_000_000):  # bounded by the socket's life
                message = await self._message()
                if message is None:
                    break
                kind, reqid = message.msgtype, message.header.get("reqid")
                if kind == "ERROR":
                    text = str(message.content.get("text"))[:200]
                    self.errors.append(f"{self.name}: the server answered ERROR: {text}")
                    if reqid == self._pull_id:
                        break  # no document: the opening fails
                    self.answered += 1
                elif kind == "OK":
                    self.answered += 1
                elif kind == "PATCH-DOC" or (kind == "PULL-DOC-REPLY" and reqid == self._pull_id):
                    if kind == "PULL-DOC-REPLY":
                        self.doc = DocumentJSON(message.content["doc"])
                    else:
                        early.append(message.content)
                    if self.doc is None:  # (the server sends changes made after its reply was built, and
                        continue          # may send them first: BokehJS keeps them for after the document too)
                    try:
                        for content in early:
                            self.doc.apply_patch(content)
                    except Exception as e:  # noqa: BLE001 - a patch this client cannot follow is an error of the run
                        self.errors.append(f"{self.name}: could not apply a PATCH-DOC: {type(e).__name__}: {e}")
                        break
                    early.clear()
                self.changed.set()
        finally:
            self.closed = True
            self.changed.set()

    async def wait_until(self, predicate, timeout: float) -> bool:
        """Wait until ``predicate()`` holds after a message (True), or ``timeout`` s pass or the socket closes
        (False)."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        for _ in range(10_000_000):  # one pass per message received; ends at the deadline
            self.changed.clear()
            if predicate():
                return True
            remaining = deadline - loop.time()
            if self.closed or remaining <= 0:
                return False
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(self.changed.wait(), remaining)
        return bool(predicate())

    async def set(self, model: dict, value, release: bool) -> None:
        """Move slider ``model`` to ``value`` as a browser does: while dragged a PATCH-DOC that changes
        ``value``; on release one that changes ``value`` and then ``value_throttled`` (BokehJS's slider sets
        both together when the mouse is released). The server answers each with OK, or ERROR."""
        changes = {"value": value, "value_throttled": value} if release else {"value": value}
        model["attributes"].update(changes)
        await model_changed(model["id"], changes).send(self.socket)
        self.sent += 1

    async def show_figures(self, count: int, timeout: float = OPEN_TIMEOUT_S) -> None:
        """Do what a browser does with the first ``count`` figure places of the page when they come into view:
        report their sentinels (``app.live.WhenShown``) shown; wait until the server has drawn the figures
        in their place. A browser of 1280x720 pixels shows one at first, a reader who scrolls through all."""
        from app.explorer import Explorer

        def sentinel(name):
            return self.doc.find(lambda m: f"figure-{name}" in (m["attributes"].get("css_classes") or ()))

        if count == 0 or self.doc.slider(FT_TITLE) is None:  # not the explorer (the yardstick)
            return
        names = [n for n in Explorer._GRID if sentinel(n) is not None][:count]
        for name in names:
            data = sentinel(name)["attributes"].get("data")
            if not isinstance(data, dict) or "id" not in data:
                raise ConnectionError(f"the sentinel of figure {name} has no data model")
            await model_changed(data["id"], {"shown": True}).send(self.socket)
            self.sent += 1
        if not await self.wait_until(lambda: all(sentinel(n) is None for n in names), timeout):
            raise TimeoutError(f"the figures {names} were not drawn in {timeout:.0f} s")

    def slider(self, title):
        """The slider titled ``title`` in the session's document (see :meth:`DocumentJSON.slider`)."""
        return self.doc.slider(title)

    def run_card(self):
        """The run card of the session's document (see :meth:`DocumentJSON.run_card`)."""
        return self.doc.run_card()

    async def close(self):
        """Close the websocket (the server drops the session) and wait up to 5 s for the reader to end."""
        with contextlib.suppress(Exception):
            self.ws.close(1000, "closed")
        if self._reader is not None:
            with contextlib.suppress(Exception):
                await asyncio.wait_for(self._reader, 5.0)
            self._reader.cancel()


def _fresh_values():
    # values never used before by any session: every release is a new solve
    ft = (round(0.05 + (0.8 * ((i * 0.618034) % 1.0)), 4) for i in itertools.count(1))
    w = (round(0.1 + (0.75 * ((i * 0.414214) % 1.0)), 4) for i in itertools.count(1))
    return {"ft": ft, "w": w}


async def _open(url, k, stats, arguments=None) -> Session | None:
    """Open session ``k`` of ``url`` and have the figures in view drawn (``stats["figures_in_view"]``, see
    :meth:`Session.show_figures`); its opening time [s] goes to ``stats["loads"]``, a failure to the errors."""
    t0 = time.monotonic()
    try:
        s = await Session.open(url, arguments, name=f"session {k}", errors=stats["errors"])
        try:
            await s.show_figures(stats.get("figures_in_view", FIGURES_IN_VIEW))
        except BaseException:
            await s.close()
            raise
        stats["loads"].append(time.monotonic() - t0)
        return s
    except Exception as e:  # noqa: BLE001 - a session that did not open is an error of the run
        stats["errors"].append(f"session {k} did not open: {type(e).__name__}: {str(e)[:200]}")
        return None


def _run_text(s: Session):
    """The text of the card that describes the run shown, or None while the cards wait for a solve."""
    card = s.run_card()
    return None if card is None else card["attributes"]["text"]


async def _work(s: Session, k, deadline, fresh, stats):
    """Drag and release sliders on session ``k`` until ``deadline()`` (a time.monotonic() value)."""
    ft, w = s.slider(FT_TITLE), s.slider(W_TITLE)
    if ft is None or w is None or s.run_card() is None:
        stats["errors"].append(f"session {k}: no ft/w slider or run card in the document")
        return
    for i in range(MAX_ROUND_TRIPS_PER_SESSION):
        if time.monotonic() > deadline():
            return
        # as a hand does it: drag one slider (the analytical layers follow, nothing is solved), then release
        # that same slider at a value no session has used (a new solve). The explorer waits for the release
        # of a slider being dragged before it solves, so releasing another one would not end the drag.
        slider, key = (w, "w") if i % 3 == 2 else (ft, "ft")
        for j in range(3):
            await s.set(slider, round(0.1 + 0.25 * j + 0.01 * (k % 10), 4), release=False)
            await asyncio.sleep(0.05)  # the server's updates come in meanwhile
        before = _run_text(s)  # None while the cards wait for a release ('release the slider')
        t0 = time.monotonic()
        await s.set(slider, next(fresh[key]), release=True)
        if await s.wait_until(lambda: _run_text(s) not in (None, before), ROUND_TRIP_TIMEOUT_S):
            stats["latencies"].append((time.monotonic() - t0) * 1e3)
        else:
            why = "the socket closed" if s.closed else f"it did not finish in {ROUND_TRIP_TIMEOUT_S:.0f} s"
            stats["errors"].append(f"session {k}: a solve round trip failed: {why}")
            return


async def _session(url, k, start_at, deadline, fresh, stats, up):
    """Session ``k``: open at ``start_at`` (time.monotonic()), move sliders until ``deadline()`` if given, close."""
    await asyncio.sleep(max(0.0, start_at - time.monotonic()))
    s = await _open(url, k, stats, {"ft": "0.3", "w": f"{0.2 + 0.02 * (k % 20):.2f}"})
    up.append(time.monotonic() if s is not None else math.nan)  # a failed session ends its opening too
    if s is None:
        return
    try:
        if deadline is not None:
            await _work(s, k, deadline, fresh, stats)
    except Exception as e:  # noqa: BLE001
        stats["errors"].append(f"session {k}: {type(e).__name__}: {str(e)[:200]}")
    finally:
        await s.close()
        stats["patches_sent"] = stats.get("patches_sent", 0) + s.sent
        stats["patches_answered"] = stats.get("patches_answered", 0) + s.answered


async def _together(coroutines, timeout: float, stats) -> None:
    """Run ``coroutines`` on this loop at once; those still running after ``timeout`` s are cancelled (an error)."""
    tasks = [asyncio.ensure_future(c) for c in coroutines]
    _, pending = await asyncio.wait(tasks, timeout=timeout)
    for t in pending:
        t.cancel()
    if pending:
        stats["errors"].append(f"{len(pending)} sessions still running after {timeout:.0f} s were cancelled")
        await asyncio.wait(pending, timeout=10.0)


@contextlib.contextmanager
def _liveness(base, stats, key, period=0.25):
    """Poll /liveness every ``period`` s in a thread while the block runs; latencies [ms] go to ``stats[key]``."""
    stop = threading.Event()

    def poll():
        for _ in range(1_000_000):  # bounded; ends with the block
            if stop.is_set():
                return
            t0 = time.monotonic()
            try:
                _health(base)
            except Exception as e:  # noqa: BLE001
                stats["errors"].append(f"liveness ({key}) failed after {time.monotonic() - t0:.1f} s: {type(e).__name__}")
            stats[key].append((time.monotonic() - t0) * 1e3)
            stop.wait(period)

    thread = threading.Thread(target=poll, daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join(LIVENESS_LIMIT_S + 5)


async def _cpu_per_session(url, pid, n, stats, arguments=None) -> tuple[float, float]:
    """Server CPU [s] per session of ``url``: ``n`` sessions opened one after another (after one untimed);
    returns it and this process's CPU [s] per session (the load generator's own)."""
    quiet = {"loads": [], "errors": stats["errors"], "figures_in_view": stats["figures_in_view"]}
    s = await _open(url, -1, quiet, arguments)
    if s is not None:
        await s.close()
    await asyncio.sleep(0.5)
    c0, own0 = _cpu_s(pid), time.process_time()
    for k in range(n):
        s = await _open(url, k, quiet, arguments)
        if s is not None:
            await s.close()
    own = time.process_time() - own0
    await asyncio.sleep(1.0)  # the server finishes with the closed sessions
    return (_cpu_s(pid) - c0) / n, own / n


def _run(url, base, pid, sessions, open_over, seconds, burst, cpu_sessions, figures_in_view):
    stats = {"errors": [], "latencies": [], "liveness": [], "liveness_burst": [], "loads": [], "patches_sent": 0,
             "patches_answered": 0, "figures_in_view": figures_in_view}
    yard = url.rsplit("/", 1)[0] + "/yardstick"
    # the loop watch's window starts here, not at the server's start: the warm-up's collector passes (0.13-0.2 s,
    # in its own thread, before /liveness says ready) stretched whatever the loop ran meanwhile
    _health(base, reset=True)
    # 1. CPU per session, one after another
    stats["cpu_explorer_s"], stats["client_cpu_explorer_s"] = asyncio.run(
        _cpu_per_session(url, pid, cpu_sessions, stats))
    stats["cpu_yardstick_s"], stats["client_cpu_yardstick_s"] = asyncio.run(
        _cpu_per_session(yard, pid, cpu_sessions, stats))
    _loop_ms(base, stats, "cpu")
    # 2. burst: sessions open at once while /liveness is polled
    up: list = []
    with _liveness(base, stats, "liveness_burst"):
        asyncio.run(_together([_session(url, 1000 + k, 0.0, None, None, stats, up) for k in range(burst)],
                              OPEN_TIMEOUT_S + 10, stats))
    _loop_ms(base, stats, "burst")
    stats["loads_burst"], stats["loads"] = stats["loads"], []
    # 3. the class: sessions spread over open_over seconds, each then moves sliders until `seconds` after
    # the last one is up (or failed), so that all of them work together for that long
    time.sleep(1.0)
    stats["rss_before_mb"] = _rss_mb(pid)
    fresh = _fresh_values()
    t0 = time.monotonic()
    up = []
    hard_end = t0 + open_over + OPEN_TIMEOUT_S + seconds

    def deadline():
        if len(up) < sessions:
            return hard_end
        opened = [t for t in up if not math.isnan(t)]
        return min(hard_end, max(opened, default=t0) + seconds)

    starts = [t0 + open_over * k / max(1, sessions - 1) if sessions > 1 else t0 for k in range(sessions)]
    cpu0, own0 = _cpu_s(pid), time.process_time()
    with _liveness(base, stats, "liveness"):
        asyncio.run(_together([_session(url, k, starts[k], deadline, fresh, stats, up) for k in range(sessions)],
                              max(1.0, hard_end + ROUND_TRIP_TIMEOUT_S + 10 - time.monotonic()), stats))
    opened = [t for t in up if not math.isnan(t)]
    stats["all_up_s"] = (max(opened) - t0) if len(opened) == sessions else float("nan")
    stats["wall_s"] = time.monotonic() - t0
    stats["cpu_class_s"] = _cpu_s(pid) - cpu0
    stats["client_cpu_class_s"] = time.process_time() - own0
    _loop_ms(base, stats, "class")
    time.sleep(2.0)  # let the server drop the closed sessions
    stats["rss_after_mb"] = _rss_mb(pid)
    return stats


def run_load(sessions: int = 60, open_over: float = 30.0, seconds: float = 60.0, burst: int = 10,
             cpu_sessions: int = 10, cluster: int = 0, env: dict | None = None, keep_log: str | None = None,
             serve_args: tuple[str, ...] = (), figures_in_view: int = FIGURES_IN_VIEW) -> dict:
    """Serve the app (and the yardstick), run the three phases; return the figures.

    Each explorer session has its first ``figures_in_view`` figures drawn as it
    opens (what a browser window shows: 1 at 1280x720; 7 for a reader who
    scrolls through the cylinder's page).

    Returns
    -------
    dict
        ``errors`` (list of messages), ``latencies`` (solve round trips, ms),
        ``liveness`` and ``liveness_burst`` (ms), ``loads`` and
        ``loads_burst`` (s), ``all_up_s``, ``cpu_explorer_s``,
        ``cpu_yardstick_s`` (server CPU per session), ``client_cpu_explorer_s``,
        ``client_cpu_yardstick_s`` (this process's CPU per session),
        ``cpu_class_s`` and ``client_cpu_class_s`` (server and this process
        over the class phase), ``patches_sent`` and ``patches_answered``
        (slider messages and each page's ready, and the server's OK or ERROR replies to them), ``loop_lag_*_ms``
        and ``loop_callback_*_ms`` (per phase: ``cpu``, ``burst``, ``class``),
        ``rss_before_mb``, ``rss_after_mb``, ``cache_mb``, ``cluster_tasks``
        (solves the Dask cluster ran) and the server's ``returncode``.
    """
    if not (1 <= sessions <= 200 and 0 <= open_over <= 600 and 1 <= seconds <= 3600 and 1 <= burst <= 100
            and 1 <= cpu_sessions <= 100 and 0 <= cluster <= 8 and 0 <= figures_in_view <= 13):
        raise ValueError("sessions in [1, 200], open_over in [0, 600] s, seconds in [1, 3600], burst in [1, 100], "
                         "cpu_sessions in [1, 100], cluster in [0, 8] workers, figures_in_view in [0, 13]")
    env = {**(env or {}), "SHAKEDOWN_LOOP_WATCH_MS": "50"}
    with tempfile.TemporaryDirectory() as tmp, contextlib.ExitStack() as stack:
        if cluster:
            address = stack.enter_context(dask_cluster(cluster))
            env["SHAKEDOWN_SCHEDULER"] = address
        log_path = Path(tmp) / "server.log"
        info: dict = {}
        with served_app(env=env, log_path=log_path, info=info, extra_args=serve_args, extra_apps=[YARDSTICK]) as url:
            stats = _run(url, info["base"], info["pid"], sessions, open_over, seconds, burst, cpu_sessions,
                         figures_in_view)
            stats["cluster_tasks"] = tasks_done(env["SHAKEDOWN_SCHEDULER"], SOLVE_TASK) if cluster else 0
        log = log_path.read_text(errors="replace")
        if keep_log:
            Path(keep_log).write_text(log)
    bad, noise = classify_server_log(log)
    stats["server_log_errors"], stats["disconnect_noise"] = bad, len(noise)
    stats["errors"] += [f"server log: {rec.splitlines()[0][:200]} ... {rec.splitlines()[-1][:200]}" for rec in bad]
    stats["errors"] += [f"liveness took {max(v) / 1e3:.1f} s (> {LIVENESS_LIMIT_S:.0f} s)"
                        for v in (stats["liveness"], stats["liveness_burst"]) if v and max(v) > LIVENESS_LIMIT_S * 1e3]
    stats["returncode"] = info.get("returncode")
    stats["stop_s"] = info.get("stop_seconds", float("nan"))
    stats["cache_mb"] = limits.CACHE_MB
    stats.update(figures_in_view=figures_in_view, sessions=sessions, open_over=open_over, seconds=seconds,
                 burst=burst, cpu_sessions=cpu_sessions,
                 cluster=cluster, serve_args=list(serve_args))
    return stats


def _summary(values, unit="ms"):
    if not values:
        return "none"
    return (f"median {statistics.median(values):.0f} {unit}, p95 {_percentile(values, 0.95):.0f} {unit}, "
            f"max {max(values):.0f} {unit}")


def _goal(ok: bool) -> str:
    return "met" if ok else "NOT met"


def report(stats: dict) -> str:
    ratio = stats["cpu_explorer_s"] / stats["cpu_yardstick_s"] if stats["cpu_yardstick_s"] > 0 else float("nan")
    burst_max = max(stats["liveness_burst"]) / 1e3 if stats["liveness_burst"] else float("nan")
    longest = max(stats[f"loop_callback_{p}_ms"] for p in ("cpu", "burst", "class")) / 1e3
    where = (f"solves on a loopback Dask cluster of {stats['cluster']} workers ({stats['cluster_tasks']} solves ran there)"
             if stats["cluster"] else "solves in the server's threads")
    lines = [
        f"server: panel serve {' '.join(stats['serve_args']) or '(default options)'}; {where}; each explorer "
        f"session has its first {stats['figures_in_view']} figure(s) drawn (a browser draws those in view)",
        f"errors: {len(stats['errors'])} (goal 0)" + "".join(f"\n  - {e}" for e in stats["errors"][:20]),
        f"server CPU per session, opened one after another ({stats['cpu_sessions']} each): explorer "
        f"{stats['cpu_explorer_s']:.2f} s, yardstick {stats['cpu_yardstick_s']:.2f} s, ratio {ratio:.1f} "
        f"(goal <= 2: {_goal(ratio <= 2)}); the load generator's own CPU per session: explorer "
        f"{stats['client_cpu_explorer_s']:.2f} s, yardstick {stats['client_cpu_yardstick_s']:.2f} s",
        f"{stats['burst']} sessions opening at once: /liveness {_summary(stats['liveness_burst'])} "
        f"(goal < 2 s: {_goal(burst_max < 2)}); opening {_summary([x * 1e3 for x in stats['loads_burst']])}",
        f"{stats['sessions']} sessions opening over {stats['open_over']:.0f} s: all up after {stats['all_up_s']:.1f} s; "
        f"opening {_summary([x * 1e3 for x in stats['loads']])}",
        f"  then sliders for {stats['seconds']:.0f} s: {len(stats['latencies'])} solve round trips, "
        f"{_summary(stats['latencies'])}; the server answered {stats['patches_answered']} of the "
        f"{stats['patches_sent']} messages (the page's ready, the sliders'; OK or ERROR)",
        f"  /liveness meanwhile: {len(stats['liveness'])} checks, {_summary(stats['liveness'])}",
        f"  CPU over the whole phase: server {stats['cpu_class_s']:.1f} s, load generator (this process) "
        f"{stats['client_cpu_class_s']:.1f} s, in {stats['wall_s']:.0f} s of wall time",
        f"longest single callback of the event loop (a session's build, a slider's update): "
        f"{stats['loop_callback_cpu_ms'] / 1e3:.2f} s (one session at a time), "
        f"{stats['loop_callback_burst_ms'] / 1e3:.2f} s (burst), {stats['loop_callback_class_ms'] / 1e3:.2f} s "
        f"(class) (goal <= 0.5 s: {_goal(longest <= 0.5)})",
        f"  the garbage collector's longest pass (it stops every thread, the loop's too): "
        f"{stats['gc_cpu_ms'] / 1e3:.2f} s, {stats['gc_burst_ms'] / 1e3:.2f} s, {stats['gc_class_ms'] / 1e3:.2f} s; "
        f"after the class: {stats['heap'].get('sessions_open')} sessions open, {stats['heap'].get('gc_reclaims')} "
        f"reclaims of ended sessions' objects (longest {stats['heap'].get('gc_reclaim_max_ms')} ms)",
        f"event loop busy without a break at most (callbacks queued together run back to back): "
        f"{stats['loop_lag_cpu_ms'] / 1e3:.2f} s (one session at a time), {stats['loop_lag_burst_ms'] / 1e3:.2f} s "
        f"(burst), {stats['loop_lag_class_ms'] / 1e3:.2f} s (class); the watch's resolution: a no-op every "
        f"{stats['loop_watch_interval_ms']:.0f} ms, its thread late by at most {stats['watch_late_cpu_ms']:.0f}, "
        f"{stats['watch_late_burst_ms']:.0f}, {stats['watch_late_class_ms']:.0f} ms",
        f"server memory (RSS): {stats['rss_before_mb']:.0f} MB before, {stats['rss_after_mb']:.0f} MB after "
        f"({stats['rss_after_mb'] - stats['rss_before_mb']:+.0f} MB; the result cache is bounded at {stats['cache_mb']} MB)",
        f"server stopped with exit code {stats['returncode']} in {stats['stop_s']:.1f} s; "
        f"disconnect noise in its log: {stats['disconnect_noise']} records",
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sessions", type=int, default=60)
    ap.add_argument("--open-over", type=float, default=30.0, help="seconds over which the sessions open")
    ap.add_argument("--seconds", type=float, default=60.0, help="seconds of slider activity after the last opening")
    ap.add_argument("--burst", type=int, default=10, help="sessions opened at once while /liveness is timed")
    ap.add_argument("--cpu-sessions", type=int, default=10, help="sessions per page for the CPU per session")
    ap.add_argument("--cluster", type=int, default=0, help="solve on a loopback Dask cluster of this many workers")
    ap.add_argument("--figures-in-view", type=int, default=FIGURES_IN_VIEW,
                    help="figures each session has drawn (1: a 1280x720 window; 7: scrolled through)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    ap.add_argument("--log", help="keep the server's log in this file")
    ap.add_argument("--serve-args", default="", help="further 'panel serve' options, e.g. '--num-threads 4'")
    args = ap.parse_args(argv)
    # stopped with SIGTERM: unwind, so that the server and the cluster this script started are stopped too
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    stats = run_load(args.sessions, args.open_over, args.seconds, args.burst, args.cpu_sessions, args.cluster,
                     keep_log=args.log, serve_args=tuple(args.serve_args.split()), figures_in_view=args.figures_in_view)
    print(report(stats))
    if args.json:
        Path(args.json).write_text(json.dumps(stats, indent=1))
    return 0 if not stats["errors"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
