"""The explorer's bodies come from core.geometry.registry: the selector, each body's parameters as inputs kept in the URL,
its run, its figures, its limit, and a body registered later (or one the explorer cannot run yet).

Headless (no browser): :class:`app.explorer.Explorer` over :class:`app.state.ExplorerState`; the runs are short
(2 periods; the demo height map on its own 32 x 32 grid of a/10).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import core
from app import bodies, plots, regime_map, sketch
from app.cards import body_limits
from app.explorer import Explorer
from app.state import BODIES, URL_PARAMETERS, ExplorerState, parse_query
from core.geometry.registry import REGISTRY

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
QUICK = "ft=0.3&w=0.5&periods=2&point_resolution=4&kernel=plane"


def test_the_selector_offers_the_registry_in_its_order():
    assert BODIES == tuple(REGISTRY) and BODIES[0] == "cylinder"
    assert {"punch", "heightmap", "sphere", "ellipsoid"} <= set(BODIES)
    assert list(ExplorerState.param.body.objects) == list(BODIES)


@pytest.mark.parametrize("body", [b for b in BODIES if REGISTRY[b].parameters])
def test_each_parameter_is_an_input_with_the_registrys_default_range_and_doc(body):
    for p in REGISTRY[body].parameters:
        name = bodies.state_name(body, p.name)
        assert name in URL_PARAMETERS, name
        spec = ExplorerState.param[name]
        # the registry's doc, in a user's words: the tooltip sits beside the body's own inputs, shown under that
        # body only, so it names no body ('; body = punch' was a developer's notation, removed in issue 31)
        assert p.doc[1:] in spec.doc and "body =" not in spec.doc, spec.doc
        assert bodies.label(body, p.name) == spec.label and "_" not in spec.label, spec.label
        if p.path:
            assert ExplorerState().param[name].default == "demo"
            continue
        assert spec.default == p.default and spec.bounds == (p.lo, p.hi), name
        assert f"in [{float(p.lo):g}, {float(p.hi):g}{']' if p.hi_closed else ')'}" in spec.doc, spec.doc
        assert spec.inclusive_bounds == (True, p.hi_closed), name


def test_a_link_with_a_body_and_its_parameters_opens_them():
    updates, errors, ignored = parse_query("?body=punch&flat=0.8")
    assert updates == {"body": "punch", "flat": 0.8} and errors == [] == ignored
    ex = Explorer(query=f"body=punch&flat=0.8&{QUICK}")
    assert ex.state.body == "punch" and ex.state.flat == 0.8
    assert ex.result.body_spec == core.Punch(flat=0.8)
    # out of the registry's range [0, 1): rejected naming the parameter and its range, the rest applied
    updates, errors, _ = parse_query("?body=punch&flat=1")
    assert updates == {"body": "punch"} and errors == ["flat must be in [0, 1), got '1'"]
    updates, errors, _ = parse_query("?body=heightmap&file=../../etc/passwd")
    assert "file" not in updates and errors[0].startswith("file must be")


@pytest.fixture(scope="module", params=BODIES)
def explorer(request):
    """An explorer of each body of the registry, solved (a short run)."""
    ex = Explorer(query=f"body={request.param}&{QUICK}")
    assert ex.error == "" and ex.result is not None, ex.error
    return ex


def test_every_body_runs_with_its_figures_verdict_and_limit(explorer):
    ex = explorer
    body, spec = ex.state.body, ex.state.body_object()
    kind = REGISTRY[body].kind
    point = isinstance(ex.result, core.PointContactResult)
    assert point == (kind == "point")
    run_body = ex.result.body if point else (ex.result.body_spec or core.Cylinder())
    assert type(run_body) is type(spec)
    # the figures of its kind, each with data from the run
    names = ex._figures_of(body)
    assert "sketch" in names and "map" in names
    assert ("point_cut" in names) == point and ("pressure" in names) == (not point)
    inputs = ex._inputs()
    for name in names:
        data = plots.layers(name, inputs)
        assert len(data) == len(plots.specs(name, inputs.units)), name
    # the verdict badge names the body's own limit; the cards give it
    badge = ex._badge(0.3, 0.5, ex.result, ex.error)
    assert f"data-regime=\"{ex.result.regime}\"" in badge
    lim, wlim = body_limits(0.3, 0.5, "cylinder" if body == "cylinder" else spec)
    assert lim == pytest.approx(float(core.ft_limit(0.5, body=spec if body != "cylinder" else "cylinder")))
    rows = dict(ex._card_rows(0.3, 0.5, ex.state.mu, ex.contact, ex.result)[0])
    key = "ft_lim(w) (eq 35)" if body == "cylinder" else f"ft_lim(w), {body} (exact)"
    # the limit to 4 decimals at least, and as many more as keep it on its side of ft (issue 31, item 4)
    shown = rows[key]
    assert re.fullmatch(r"\d\.\d{4,6}", shown) and float(shown) == pytest.approx(lim, abs=5e-5), rows
    assert (float(shown) - 0.3) * (lim - 0.3) > 0, rows
    # and the limit of the run's own grid, which its verdict is checked against (Melan on its lowest pressure)
    lo, hi = ex.result.melan_limit
    grid = rows["ft_lim on this grid (Melan)"]
    assert grid == (f"{lo:.4g}" if lo == hi else f"{lo:.4f} – {hi:.4f}"), grid
    assert lo == pytest.approx(lim, rel=0.05)  # the grid's limit is the exact one to the grid's accuracy


def test_the_map_draws_the_bodys_own_limit_curve(explorer):
    ex = explorer
    body, spec = ex.state.body, ex.state.body_object()
    ft, w = regime_map.body_limit(ex.result)
    if body == "cylinder" or bodies.is_ellipsoid(spec):  # drawn already: eq 35 and the ellipsoids' closed form
        assert ft.size == 0
        return
    assert ft.size >= 8 and ft[0] == pytest.approx(1.0) and np.all(np.diff(ft) <= 1e-12)
    k = len(w) // 2
    assert ft[k] == pytest.approx(float(core.ft_limit(w[k], body=spec)), rel=1e-9)


def test_the_sketch_draws_each_body(explorer):
    ex = explorer
    ground, centre_range, pressure, outline, spoke, patch, arrow, trailing = sketch.layers(ex._inputs())
    assert len(outline[0]) > 50 and np.all(np.isfinite(outline[1]))
    assert len(pressure[0]) > 5 and np.nanmin(pressure[1]) < 0  # the pressure drawn below the ground
    assert len(patch[0]) == 2 and patch[0][1] > patch[0][0]


def test_downloads_name_the_body(explorer):
    ex = explorer
    ex._name_downloads()
    body = ex.state.body
    name = ex.json_download.filename
    assert (body in name) == (body != "cylinder"), name
    data = json.loads(ex._json().getvalue())
    assert data["parameters"]["regime"] == ex.result.regime


def test_a_parameter_change_reruns_and_moves_the_verdict_and_curves():
    """The punch at w = 0.5: ft_lim = 0.383 at flat 0.5 and 0.344 at flat 0.8 (Melan), so ft = 0.36 is predicted to
    shake down with the first and to ratchet with the second; the run, the curves and the cards follow."""
    lo, hi = (float(core.ft_limit(0.5, body=core.Punch(flat=f))) for f in (0.8, 0.5))
    assert lo < 0.36 < hi
    ex = Explorer(query="body=punch&flat=0.5&ft=0.36&w=0.5&periods=2&kernel=plane")
    assert "predicts shakedown" in ex._badge(0.36, 0.5, ex.result, ex.error)
    before = plots.layers("pressure", ex._inputs())[3]  # μ p_min
    ex.state.flat = 0.8
    assert ex.result.body_spec == core.Punch(flat=0.8)
    assert "predicts ratcheting" in ex._badge(0.36, 0.5, ex.result, ex.error)
    after = plots.layers("pressure", ex._inputs())[3]
    assert not np.allclose(before[1], after[1])
    # the punch's flat: its pressure at the centre is lower than the cylinder's peak, flat-topped with edge peaks
    x, p = plots.layers("pressure", ex._inputs())[0]
    assert p[np.argmin(np.abs(x))] < p.max()


def test_the_demo_height_map_is_the_documented_shape():
    h = bodies.demo_heights()
    assert h.shape == (bodies.DEMO_GRID,) * 2 and np.array_equal(h, bodies.demo_heights())  # seeded
    hm = bodies.make("heightmap", {"file": "demo", "length_unit": 1.0, "height_unit": 1.0})
    assert hm is bodies.make("heightmap", {"file": "demo"})  # one object per body and parameters (shared)
    assert hm.spacing == pytest.approx(bodies.DEMO_SPACING, rel=1e-6)
    contact = hm.solve().contact
    rows, cols = np.nonzero(contact)
    assert rows.min() > 0 and cols.min() > 0 and rows.max() < h.shape[0] - 1  # inside the map
    # flat-topped: a lower limit than the sphere's at the same w (its pressure is flatter, p_min a smaller share)
    assert float(core.ft_limit(0.5, body=hm)) < 1.0


def test_an_uploaded_map_is_a_source_any_session_opens(tmp_path):
    """A height map uploaded as a file (any format SurfaceTopography reads): stored by its digest, named in the
    URL, opened by a second explorer from that URL."""
    from SurfaceTopography import Topography

    n, h = 40, 0.1
    x = (np.arange(n) - n // 2) * h
    X, Y = np.meshgrid(x, x, indexing="ij")
    path = tmp_path / "sphere.nc"
    Topography(-0.375 * (X**2 + Y**2), (n * h, n * h)).to_netcdf(str(path))
    source = bodies.store_upload(path.read_bytes(), "sphere.nc")
    assert bodies.SOURCE_PATTERN.match(source) and bodies.uploaded(source).nb_grid_pts == (n, n)
    ex = Explorer(query=f"body=heightmap&file={source}&{QUICK}")
    assert ex.error == "" and isinstance(ex.result, core.PointContactResult)
    hm = ex.state.body_object()
    assert hm.heights.shape == (n, n)
    # Hertz's sphere sampled: the sphere's closed-form limit to the grid's accuracy
    assert float(core.ft_limit(0.3, body=hm)) == pytest.approx(float(core.ft_limit(0.3, body="sphere")), abs=0.03)
    missing = Explorer(query=f"body=heightmap&file=upload-{'0' * 16}&{QUICK}")
    assert "no file" in missing.error and missing.contact is None
    with pytest.raises(ValueError, match="empty"):
        bodies.store_upload(b"", "x.nc")


def test_the_panel_inputs_are_built_from_the_registry():
    import panel as pn

    ex = Explorer(query=f"body=punch&{QUICK}")
    page = pn.Column(*__import__("app.point_view", fromlist=["x"]).body_inputs(ex.state))
    sliders = [w for w in page.select(pn.widgets.FloatSlider)]
    flat = [s for s in sliders if s.label == "Flat part b/a"]  # the registry's flat in a user's words
    assert len(flat) == 1 and flat[0].start == 0.0 and flat[0].end < 1.0 and flat[0].value == 0.5
    tips = [t.value for t in page.select(pn.widgets.TooltipIcon)]
    assert any("b/a" in t for t in tips)  # the registry's doc as the tooltip
    ex.state.body = "heightmap"  # its inputs are built when first chosen
    assert any(s.value == "demo" for s in page.select(pn.widgets.Select))
    assert page.select(pn.widgets.FileInput)
    notes = [m.object for m in page.select(pn.pane.Markdown) if "heightmap" in str(m.object)]
    assert notes and "own grid" in notes[0]


_LATE_BODY = textwrap.dedent("""
    import json, sys
    import core
    from core.geometry.registry import BodyEntry, Parameter, register

    def _wide_punch(flatness=0.3):
        return core.Punch(flat=flatness)

    class _OnlyALimit:
        name = "limitonly"

    register(BodyEntry("widepunch", _wide_punch, "line", "a punch registered late, in a test",
                       (Parameter("flatness", 0.3, 0.0, 0.9, "its flat over its contact half-width"),)))
    register(BodyEntry("limitonly", _OnlyALimit, "point", "a body whose cycles cannot run yet"))

    from app.explorer import Explorer
    from app.state import BODIES

    ex = Explorer(query="body=widepunch&flatness=0.6&ft=0.3&w=0.5&periods=2&kernel=plane")
    limited = Explorer(query="body=limitonly&ft=0.3&w=0.5")
    print(json.dumps({"bodies": list(BODIES), "spec": repr(ex.result.body_spec), "error": ex.error,
                      "regime": ex.result.regime, "limited": limited.error,
                      "badge": limited._badge(0.3, 0.5, limited.result, limited.error)}))
""")


def test_a_body_registered_in_core_appears_and_runs_and_one_that_cannot_run_shows_its_limit_only():
    """A body registered in core.geometry.registry (here in a subprocess, before the app is imported) is in the selector,
    its parameter in the URL, its run on the 1D engine; a body whose cycles the explorer cannot run (the cone
    before its runs exist) is shown as 'limit only', not as an error."""
    out = subprocess.run([sys.executable, "-c", _LATE_BODY], capture_output=True, text=True, timeout=600,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": ROOT})
    assert out.returncode == 0, out.stderr[-3000:]
    got = json.loads(out.stdout.strip().splitlines()[-1])
    assert got["bodies"][-2:] == ["widepunch", "limitonly"]
    assert got["spec"] == "Punch(flat=0.6)" and got["error"] == ""
    assert got["limited"].startswith("limit only") and "LIMIT ONLY" in got["badge"]


def test_the_map_draws_a_sweep_only_beside_runs_of_its_body_and_parameters():
    """The shipped map is the cylinder's: not drawn beside a punch run; a map computed for the punch (its object,
    with its flat) is, and not beside another flat."""
    regimes = len(regime_map._MAP_REGIMES)  # the runs' layers, one per regime (issue 30 added cyclic slip: four)
    ex = Explorer(query="body=punch&flat=0.8&ft=0.3&w=0.5&periods=1&kernel=plane")
    shown = plots.layers("map", ex._inputs())
    assert all(len(layer.data[0]) == 0 for layer in shown[:regimes])  # the shipped cylinder map is not drawn
    ex.map_points.value = 3
    ex.compute_map()
    assert ex.map_table is not None and set(ex.map_table["body"]) == {"Punch(flat=0.8)"}, ex.map_status
    shown = plots.layers("map", ex._inputs())
    assert sum(len(layer.data[0]) for layer in shown[:regimes]) == 9
    ex.state.flat = 0.5
    shown = plots.layers("map", ex._inputs())
    assert all(len(layer.data[0]) == 0 for layer in shown[:regimes])


def test_uploading_a_file_in_the_page_opens_it_and_a_bad_one_is_reported(tmp_path):
    """The height map's upload button: a readable map becomes the body (its source in the URL); a file
    SurfaceTopography cannot read is an invalid input naming the reason, not a server error."""
    import panel as pn
    from SurfaceTopography import Topography

    from app import point_view

    ex = Explorer(query=f"body=heightmap&{QUICK}")
    page = pn.Column(*point_view.body_inputs(ex.state))
    upload = page.select(pn.widgets.FileInput)[0]
    n, h = 36, 0.1
    x = (np.arange(n) - n // 2) * h
    X, Y = np.meshgrid(x, x, indexing="ij")
    path = tmp_path / "bowl.nc"
    Topography(-0.375 * (X**2 + Y**2), (n * h, n * h)).to_netcdf(str(path))
    upload.param.update(filename="bowl.nc", value=path.read_bytes())
    assert ex.state.file.startswith("upload-") and ex.error == ""
    assert ex.state.body_object().heights.shape == (n, n) and ex.result.body is ex.state.body_object()
    select = [s for s in page.select(pn.widgets.Select) if s.value == ex.state.file]
    assert select and "demo" in select[0].options.values()  # back to the demo is one choice away
    upload.param.update(filename="notes.txt", value=b"not a height map at all")
    assert ex.contact is None and "cannot be built" in ex.error and "heightmap" in ex.error
    # the same words as the command line's (core.geometry.heightmap.read_topography), every readable format named
    from core.geometry.heightmap import readable_formats

    assert "the uploaded file notes.txt is in no format that can be read; the readable formats: " in ex.error
    assert all(f in ex.error for f in readable_formats()) and "Network Common Data Format (NetCDF) (.nc)" in ex.error
    badge = ex._badge(ex.state.ft, ex.state.w, ex.result, ex.error)
    assert "INVALID INPUT" in badge and "notes.txt is in no format that can be read" in badge
    assert "(NetCDF) (.nc)" in badge
    select[0].value = "demo"
    assert ex.state.file == "demo" and ex.error == ""
