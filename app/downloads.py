"""Downloads of the run shown: CSV (one table) and JSON (every table), written by :mod:`core.api.export`.

:class:`DownloadsMixin` builds the table menu and the two download buttons and names the files after the run
(body, ft, w, μ, periods). The app writes no CSV or JSON itself: every body's run goes through
:func:`core.api.export.to_csv` and :func:`core.api.export.to_json`, with the periods numbered as on the cycle player
(``first_period=1``: 0 the loading, 1 the first rocking period).
"""

from __future__ import annotations

import io

import panel as pn

from core.api.export import to_csv, to_json

from . import bodies
from .cards import input_digits

__all__ = ["DownloadsMixin", "FIRST_PERIOD"]

#: The number of the first rocking period in the downloads (as on the player and the increment figure).
FIRST_PERIOD = 1


class DownloadsMixin:
    """The run's downloads (methods of :class:`app.explorer.Explorer`)."""

    def _build_downloads(self):
        self.csv_table = pn.widgets.Select(label="CSV table", options={
            "per step (displacement)": "steps", "per period (increments)": "periods",
            "final traction and zones": "final"}, value="steps", sizing_mode="stretch_width")
        self.csv_download = pn.widgets.FileDownload(callback=self._csv, filename="shakedown_steps.csv",
                                                    label="Download CSV", color="success",
                                                    sizing_mode="stretch_width", css_classes=["csv-download"])
        self.json_download = pn.widgets.FileDownload(callback=self._json, filename="shakedown_run.json",
                                                     label="Download JSON", color="success",
                                                     sizing_mode="stretch_width", css_classes=["json-download"])
        self.csv_table.param.watch(lambda e: self._name_downloads(), "value")

    def _run_contact(self):
        """The current contact if it is of the run's kind (after a body switch the run may be the other body's)."""
        if self.contact is None or self.contact.is_point != self.result.is_patch:
            return None
        return self.contact

    def _csv(self):
        if self.result is None:
            return io.StringIO("# no run yet\n")
        return io.StringIO(to_csv(self.result, self.csv_table.value, self._run_contact(), first_period=FIRST_PERIOD))

    def _json(self):
        if self.result is None:
            return io.StringIO("{}")
        return io.StringIO(to_json(self.result, self._run_contact(), first_period=FIRST_PERIOD))

    def _name_downloads(self) -> None:
        """Download names that carry the run's parameters (a folder of downloads stays readable)."""
        r = self.result
        name = None if r is None else str(getattr(r.body, "name", r.body))  # a cylinder-kind run: its body's name
        body = "" if name in (None, bodies.DEFAULT) else f"_{name}"
        if r is not None:  # ft and w to the digits that keep them on their side of the limit (app.cards.on_side)
            ft, w = input_digits(float(r.params.get("ft", 0)), float(r.params.get("w", 0)), r.body)
        tag = "" if r is None else f"{body}_ft{ft}_w{w}_mu{self.state.mu:.2f}_{r.periods}p"
        self.csv_download.filename = f"shakedown_{self.csv_table.value}{tag}.csv"
        self.json_download.filename = f"shakedown_run{tag}.json"
