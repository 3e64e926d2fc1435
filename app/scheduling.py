"""Solve scheduling: a solve per change of the inputs, in the worker pool, the stale answers dropped.

:class:`SolveMixin` gives the explorer its solve requests (:meth:`~SolveMixin._request_solve`: cached, else in
the bounded worker pool of :mod:`app.runs`, with a spinner after :data:`SPINNER_DELAY_MS`), the hand-over of a
finished run to the session (:meth:`~SolveMixin._finish`) and the batching of a change's updates
(:meth:`~SolveMixin._held`).
"""

from __future__ import annotations

import contextlib
import functools
import math
import types

import panel as pn
from panel.io.state import set_curdoc

import core
from core.api.convergence import increment_error

from . import bodies, runs
from .cards import SPINNER_DELAY_MS, coupled_beta
from .runs import RESULTS, run_key, solve, submit

__all__ = ["SolveMixin", "SPINNER_DELAY_MS"]


class SolveMixin:
    """Solving the explorer's inputs (methods of :class:`app.explorer.Explorer`)."""

    @contextlib.contextmanager
    def _held(self):
        """Batch the updates of one change: apply them now, in this session's document, held, and send them
        to the browser together when the block ends. (Not a model freeze: leaving a freeze recomputes the
        document's whole model graph, 40 ms, even when only data changed.)"""
        doc = self._doc
        if doc is None or doc.session_context is None:
            yield
            return
        with set_curdoc(doc), pn.io.hold(doc):
            yield

    def _in_session(self, fn, *args, **kwargs) -> None:
        """Run ``fn`` in a Bokeh callback of this session (document locked), so its changes are sent at once.

        Work finished in a thread or a coroutine must come back this way: changes made outside a
        locked callback wait for the next one before they reach the browser. Thread-safe: from another thread it
        goes through the session's event loop (:func:`app.runs.call_in_session`).
        """
        doc = self._doc
        if doc is None or doc.session_context is None:
            fn(*args, **kwargs)
        else:
            runs.call_in_session(doc, self._loop, functools.partial(fn, *args, **kwargs))

    # ------------------------------------------------------------------ solving
    def _inputs_changed(self, *events):
        with self._held():
            self._update_contact()
            self._request_solve()

    def _update_contact(self):
        """The contact of the inputs, or why there is none (``error``; then no run is shown: figures of other
        inputs under INVALID INPUT would be read as the answer)."""
        try:
            typed = getattr(self, "typed_errors", {})
            if typed:
                raise ValueError("; ".join(typed.values()))
            contact = self.state.contact()
        except ValueError as e:
            self.param.update(contact=None, error=str(e), result=None)
            return
        geometry = contact.replace(ft=0.0, w=0.0)
        self.param.update(contact=contact, error="",
                          **({} if geometry == self.geometry else {"geometry": geometry}))

    def _request_solve(self):
        """Solve the current inputs (cached, else in the worker pool); drop the answer if the inputs moved on."""
        token = self._generation.next()
        if self.contact is None:
            self.param.update(solving=False, pending=False)
            return
        contact, options = self.contact, self.state.solver_options()
        cached = RESULTS.get(run_key(contact, options))
        doc = self._doc
        if cached is not None or doc is None or doc.session_context is None:
            # cached, or headless (tests, notebooks without a server): solve here
            self._finish(token, contact, options, cached)
            return
        group = self._solver_group()
        if not runs.warmed(group):
            # the server's warm-up still compiles this grid's solver (a fresh install): the solve is asked for
            # once it is ready, so that it neither compiles a second time beside it nor runs out of its time
            # budget while compiling; meanwhile the page works without it (the analytical layers)
            self.pending = True
            if not getattr(self, "_awaiting_solver", False):
                self._awaiting_solver = True

                def ask():
                    self._awaiting_solver = False
                    self._request_solve()

                runs.on_warm(group, lambda: self._in_session(ask))
            return

        self.pending = True  # every card and the badge say so at once: no old verdict beside new inputs

        def show_spinner():  # only if the solve is not over in a blink (saves two page updates)
            # nor failed in a blink: a refusal that came before the delay left the spinner on for good
            if self._generation.is_current(token) and self.result_token != token and self.pending:
                self.solving = True

        doc.add_timeout_callback(show_spinner, SPINNER_DELAY_MS)

        def stale():
            return not self._generation.is_current(token)

        def failed(message):
            if stale():  # a stale run was cancelled on purpose: say nothing
                return
            if not self._back_from_refine(message):
                self.param.update(error=f"solver: {message}", solving=False, pending=False)

        def done(future):  # in the solver thread
            try:
                result = future.result()
            except (core.SolverError, core.SolveCancelled, ValueError) as e:
                self._in_session(failed, str(e))
            else:
                self._in_session(self._finish, token, contact, options, result)

        submit(contact, options, cancel=stale).add_done_callback(done)

    def _back_from_refine(self, message: str) -> bool:
        """The run of the 'Refine grid' button failed (ran out of time): go back to the grid it came from (its
        run is cached) and say so in a notice, rather than an error where a result was. False if the failed
        run was not a refinement."""
        refined_from = getattr(self, "_refined_from", None)
        if refined_from is None or refined_from == self.state.point_resolution:
            return False
        tried, self._refined_from = self.state.point_resolution, None
        self.notices = [*self.notices, f"The grid a/{tried} did not finish in time ({message}); back to a/{refined_from}."]
        self.state.point_resolution = refined_from
        return True

    def _finish(self, token, contact, options, result=None):
        if result is None:
            try:
                result = solve(contact, options)
            except (core.SolverError, core.SolveCancelled, ValueError) as e:
                if not self._back_from_refine(str(e)):
                    self.param.update(error=f"solver: {e}", solving=False, pending=False)
                return
        if not self._generation.is_current(token):
            return  # a newer request is pending: never overwrite it with this stale run
        self.result_token = token
        self._refined_from = None  # a refined grid's run arrived (or another input's): nothing to go back to
        if result is self.result:  # the same run (mu moved: a normalised run does not depend on it, app.runs.run_key)
            with self._held():
                self.param.update(plot_units=self._compute_units(result), solving=False, pending=False)
                self._name_downloads()
            return
        with self._held():
            self.play.value = False
            self._sync_player(result)  # the widgets follow the run (ranges too); the frame is set once, below
            self.param.update(result=result, frame=result.xc.size - 1, plot_units=self._compute_units(result),
                              solving=False, pending=False)
            self._name_downloads()
        if isinstance(result, core.PointContactResult):
            self._estimate_grid_error(token, contact, options, result)

    def _estimate_grid_error(self, token, contact, options, result) -> None:
        """The discretisation error of a point contact's increment (:func:`core.increment_error`):
        the same run at twice the element width (an eighth of the cost), solved like any run (cached, in the
        worker pool), then shown on the run card (:attr:`grid_error`)."""
        if "body" in options and bodies.own_grid(options["body"]):  # a body on its own fixed grid: no coarser run
            self.grid_error = types.SimpleNamespace(result=result, error=math.nan)  # the cards: "not estimated"
            return
        if 2 * result.dx > 0.5:
            return
        coarse_options = {**options, "dx": 2 * float(options.get("dx", result.dx))}
        doc = self._doc

        def show(coarse):
            if self._generation.is_current(token) and self.result is result:
                try:
                    estimate = increment_error(result, coarse)
                except ValueError:  # the runs do not pair (never expected): no error bar rather than a wrong one
                    return
                with self._held():
                    self.grid_error = estimate

        cached = RESULTS.get(run_key(contact, coarse_options))
        if cached is not None or doc is None or doc.session_context is None:
            try:
                show(cached if cached is not None else solve(contact, coarse_options))
            except (core.SolverError, core.SolveCancelled, ValueError):
                pass
            return

        def done(future):  # in the solver thread
            try:
                coarse = future.result()
            except (core.SolverError, core.SolveCancelled, ValueError):
                return
            self._in_session(show, coarse)

        submit(contact, coarse_options, cancel=lambda: not self._generation.is_current(token)).add_done_callback(done)

    def solve_now(self) -> core.CycleResult | None:
        """Solve the current inputs synchronously (headless use) and return the result."""
        self._update_contact()
        if self.contact is not None:
            self._finish(self._generation.next(), self.contact, self.state.solver_options())
        return self.result

    def _show_spinner(self, *_):
        """The status line under the badge: while the server's warm-up compiles the solver, what it does and for
        how long; else empty (watches ``solving``, ``result`` and ``error``). The running solve's spinner is the pending badge's
        (:data:`app.cards.SOLVING_BADGE`, shown by the browser after :data:`SPINNER_DELAY_MS`): only this pane's
        text changes, never a model's visibility, which made the browser lay out the whole page again."""
        compiling = self._compiling_line()
        self.status.object = ("" if compiling is None else
                              f"<div class='solve-status-line' style='padding: 6px 4px'>{compiling}</div>")

    def _solver_group(self) -> str:
        """Which of the server's warm-up groups (:func:`app.runs.on_warm`) solves the current inputs: a point
        contact's, a coupled line contact's (Dundurs β ≠ 0) or an uncoupled line contact's solver."""
        if self.state.point:
            return "point"
        return "coupled" if coupled_beta(self.contact) is not None else "line"

    def _compiling_line(self) -> str | None:
        """``compiling the solver (first start only), N s`` while the server's warm-up still compiles the solver
        of the current inputs and this session has no run yet (else None)."""
        seconds = runs.warming_seconds()
        if seconds is None or self.result is not None or self.error or runs.warmed(self._solver_group()):
            return None
        return f"compiling the solver (first start only), {seconds:.0f} s"

    def _follow_compiling(self) -> None:
        """Show :meth:`_compiling_line` now and count its seconds up, once a second, until this session's first
        run arrives (or its inputs turn out invalid)."""
        self._show_spinner()
        doc = self._doc
        holder = {}

        def tick():
            self._show_spinner()
            if self._compiling_line() is None and "callback" in holder:
                doc.remove_periodic_callback(holder.pop("callback"))

        holder["callback"] = doc.add_periodic_callback(tick, 1000)

