"""Bodies from sampled surfaces (core/geometry/heightmap.py): a line profile on the 1D engine, a height map's limit."""

import re

import numpy as np
import pytest

import core
from core.geometry.heightmap import HeightMap, HeightProfile
from core.theory.punch import punch_profile


def test_sampled_cylinder_is_the_cylinder():
    x = np.linspace(-2, 2, 1601)
    body = HeightProfile((2 / np.pi) * x**2, x[1] - x[0])
    for w in (0.1, 0.5):
        assert float(core.ft_limit(w, body=body)) == pytest.approx(float(core.ft_limit(w)), abs=5e-5)
    r = core.simulate_cycles(0.5, 0.3, periods=8, body=body)
    ref = core.simulate_cycles(0.5, 0.3, periods=8)
    assert np.allclose(r.increment_per_period, ref.increment_per_period, rtol=2e-3, atol=1e-6)
    assert r.body_name == "profile" and r.body is body


def test_measured_punch_from_a_surfacetopography_file(tmp_path):
    """A punch's profile as a 'measured' line scan in micrometres (a = 200 um, P/E* = 0.05 um), written to a
    NetCDF file and read back: its limit is the punch's, and runs 10 % either side of it shake down / ratchet."""
    import SurfaceTopography as st
    a_um, unit_um = 200.0, 0.05
    n, size = 1200, 3.0  # 3 a wide
    x = (np.arange(n) - n // 2) * size / n
    scan = st.UniformLineScan(-punch_profile(x, 0.5) * unit_um, size * a_um, unit="um")
    path = tmp_path / "scan.nc"
    scan.to_netcdf(str(path))
    body = HeightProfile.from_topography(path, length_unit=a_um, height_unit=unit_um, centre=n // 2)
    lim = float(core.ft_limit(0.3, body=body))
    assert lim == pytest.approx(float(core.ft_limit(0.3, body=core.Punch(0.5))), abs=2e-4)
    assert core.simulate_cycles(0.9 * lim, 0.3, periods=30, body=body).regime == "shakedown"
    assert core.simulate_cycles(1.1 * lim, 0.3, periods=30, body=body).regime == "ratcheting"


def test_height_map_of_a_sphere():
    """The sphere sampled on a 64 x 64 map (h = 0.05 a): Melan's limit within 0.01 of (1 - w)^2 (2 + w)/2."""
    x = (np.arange(64) + 0.5) * 0.05 - 1.6
    X, Y = np.meshgrid(x, x)
    m = HeightMap(0.375 * (X**2 + Y**2), 0.05)
    for w in (0.0, 0.2, 0.5):
        assert m.ft_limit(w) == pytest.approx(1 - 1.5 * w + 0.5 * w**3, abs=0.01)
    assert m.solve().area == pytest.approx(np.pi, rel=0.03)


def test_height_map_from_topography_object():
    import SurfaceTopography as st
    x = (np.arange(48) + 0.5) * 0.0625 - 1.5
    X, Y = np.meshgrid(x, x, indexing="ij")  # SurfaceTopography indexes (x, y)
    topo = st.Topography(-(0.375 * X**2 + 0.2 * Y**2) * 2.0, (3.0, 3.0))
    m = HeightMap.from_topography(topo, length_unit=1.0, height_unit=2.0)
    assert m.heights.shape == (48, 48)
    sol = m.solve()
    # longer along y (the flatter direction): the contact's extent in y exceeds that in x
    rows, cols = np.nonzero(sol.contact)
    assert np.ptp(rows) > np.ptp(cols)


@pytest.mark.parametrize("call, match", [
    (lambda: HeightProfile(np.zeros(3), 0.1), "heights"),
    (lambda: HeightProfile(np.linspace(-1, 1, 11) ** 2, 0.0), "spacing"),
    (lambda: HeightProfile(np.linspace(-1, 1, 11) ** 2, 0.1, centre=20), "centre"),
    (lambda: HeightProfile(np.linspace(0, 1, 11), 0.1), "centre"),
    (lambda: HeightMap(np.zeros((3, 3)), 0.1), "heights"),
    (lambda: HeightMap(np.zeros((8, 8)), 0.1).ft_limit(1.5), "w"),
    (lambda: HeightProfile.from_topography(np.zeros(5), 0.0, 1.0), "length_unit"),
])
def test_bad_inputs(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_contact_reaching_the_edge_is_refused():
    x = np.linspace(-0.5, 0.5, 101)
    with pytest.raises(ValueError, match="edge"):
        core.ft_limit(0.1, body=HeightProfile(0.01 * x**2, 0.01))


def _map(heights_of_r2, n=35, dx=0.1):
    """A map of ``n x n`` elements of side ``dx`` [a], element ``n // 2`` at the origin."""
    x = (np.arange(n) - n // 2) * dx
    X, Y = np.meshgrid(x, x)
    return HeightMap(heights_of_r2(X**2 + Y**2, X, Y), dx)


def test_sphere_map_runs_as_the_sphere():
    """The sphere's gap 0.375 r^2 sampled at a/10 runs on the 3D solver on the sphere's grid with the sphere's
    discrete bound (pressures 1e-11 apart): the increments are the sphere's (measured equal to 8 digits), with
    dW = dx (the solved pressure shifted by whole elements) and dW = 0.6 dx (solved again per fractional offset:
    linear interpolation along x of a paraboloid is exact up to a constant, which the approach absorbs)."""
    m = _map(lambda r2, X, Y: 0.375 * r2, n=31)
    for dW in (None, 0.06):
        r = core.simulate_cycles(0.4, 0.6, periods=4, body=m, dW=dW)
        s = core.simulate_cycles(0.4, 0.6, periods=4, dx=0.1, dW=dW, body="sphere")
        assert r.params["normal"] == "numerical" and r.x_edges.size == s.x_edges.size
        np.testing.assert_allclose(r.increment_per_period, s.increment_per_period, rtol=1e-6)
        np.testing.assert_allclose(r.pressure(3), s.pressure(3), atol=1e-9)
    # its Melan limit is the sphere's to the grid's accuracy (0.5644 against 0.5635 at w = 0.3)
    lim = float(core.ft_limit(0.3, body=m))
    assert lim == pytest.approx(float(core.ft_limit(0.3, body="sphere")), abs=0.005)
    # between whole elements too (turning points solved at their fractional offsets): measured within 0.0016
    for w in (0.25, 0.326, 0.55):
        assert m.ft_limit(w) == pytest.approx(float(core.ft_limit(w, body="sphere")), abs=0.002)
    with pytest.raises(ValueError, match="normal"):
        core.simulate_cycles(0.4, 0.6, periods=2, body=m, normal="exact")
    with pytest.raises(ValueError, match="spacing"):
        core.simulate_cycles(0.4, 0.6, periods=2, body=m, dx=0.05)


@pytest.mark.parametrize("name, heights, limit", [
    # a paraboloid with a flat top of radius a/2: the pressure peaks at the flat's edge (1.16 p0)
    ("flat top", lambda r2, X, Y: 0.375 * np.maximum(r2 - 0.25, 0.0), 0.5312),
    # a paraboloid with a random roughness of 0.01 P/(E* a) rms: peak pressure 1.70 p0
    ("rough", lambda r2, X, Y: 0.375 * r2 + 0.01 * np.random.default_rng(7).standard_normal(r2.shape), 0.3794),
])
def test_non_hertzian_map_brackets_its_limit(name, heights, limit):
    """Melan's limit of a non-Hertzian map (w = 0.3, a/10) bracketed by 30-period runs: 10 % below shakes down,
    10 % above ratchets. Measured: flat top 0.5312 (last increments 9e-8 and 0.0285), rough 0.3794 (1.1e-4,
    decaying, and 0.0069)."""
    m = _map(heights)
    lim = float(core.ft_limit(0.3, body=m))
    assert lim == pytest.approx(limit, abs=1e-3)
    assert core.simulate_cycles(0.9 * lim, 0.3, periods=30, body=m).regime == "shakedown"
    assert core.simulate_cycles(1.1 * lim, 0.3, periods=30, body=m).regime == "ratcheting"


def _cli(*args):
    """``shakedown ARGS`` run by core.command.cli.main in this process (a subprocess cost seconds of imports each; the
    command as a process: tests/test_cli.py): its exit status and output."""
    import contextlib
    import io
    import types

    from core.command.cli import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return types.SimpleNamespace(returncode=code, stdout=out.getvalue(), stderr=err.getvalue())


def test_cli_runs_a_height_map_file(tmp_path):
    """shakedown run --body heightmap --file map.nc: the flat-top paraboloid as a 'measured' map in micrometres
    (a = 100 um, P/(E* a) = 2 um) written to NetCDF by SurfaceTopography; 10 % below its limit it shakes down,
    and the run prints the map's Melan limit (0.5312, as from the array)."""
    import SurfaceTopography as st
    n, dx = 35, 0.1
    x = (np.arange(n) - n // 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")  # SurfaceTopography indexes (x, y)
    topo = st.Topography(-2.0 * 0.375 * np.maximum(X**2 + Y**2 - 0.25, 0.0), (n * dx * 100.0,) * 2, unit="um")
    path = tmp_path / "map.nc"
    topo.to_netcdf(str(path))
    p = _cli("run", "--ft", "0.478", "--w", "0.3", "--body", "heightmap", "--file", str(path), "--length-unit", "100",
             "--height-unit", "2", "--periods", "30")
    assert p.returncode == 0, p.stderr
    assert "heightmap, 3D half-space" in p.stdout and "shakedown" in p.stdout
    assert re.search(r"exact limit at this w +0.5312", p.stdout) and "dx = 0.1 a" in p.stdout
    for args, message in ((("--body", "heightmap"), "heightmap' needs a"),
                          (("--body", "sphere", "--file", str(path)), "--file is for --body heightmap")):
        p = _cli("run", "--ft", "0.3", "--w", "0.3", "--periods", "2", *args)
        assert p.returncode != 0 and message in p.stderr, p.stderr


def test_a_height_map_has_one_name_registry_cli_and_result():
    from core.geometry.registry import REGISTRY
    assert HeightMap.name == "heightmap" and "heightmap" in REGISTRY and REGISTRY["heightmap"].kind == "point"
    assert HeightProfile.name not in REGISTRY  # a line profile is given as an object, under its own name


def test_cli_says_a_height_map_file_is_missing_or_unreadable(tmp_path):
    """Bad input, exit 2 and one line: a file that does not exist is 'file not found: PATH'; a file no reader
    understands names every format that can be read (SurfaceTopography's own list of readers)."""
    from SurfaceTopography.IO import readers

    from core.geometry.heightmap import readable_formats

    missing = tmp_path / "missing.nc"
    p = _cli("run", "--ft", "0.3", "--w", "0.3", "--body", "heightmap", "--file", str(missing))
    assert p.returncode == 2, p.stderr
    assert p.stderr.strip() == f"shakedown: error: file not found: {missing}" and "Traceback" not in p.stderr
    notes = tmp_path / "notes.txt"
    notes.write_text("not a height map at all\n")
    p = _cli("run", "--ft", "0.3", "--w", "0.3", "--body", "heightmap", "--file", str(notes))
    assert p.returncode == 2 and "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert f"{notes} is in no format that can be read" in p.stderr
    assert len(readable_formats()) == len(readers) >= 20
    for reader, listed in zip(readers, readable_formats()):
        assert listed.startswith(reader.name()) and listed in p.stderr
    assert "Network Common Data Format (NetCDF) (.nc)" in p.stderr
    p = _cli("run", "--ft", "0.3", "--w", "0.3", "--body", "heightmap", "--file", str(tmp_path))
    assert p.returncode == 2 and f"{tmp_path} is not a file" in p.stderr, p.stderr


def test_read_topography_from_memory_and_its_errors(tmp_path):
    """The same reader for a path and for bytes in memory (an upload); its errors are ValueErrors."""
    import io

    import SurfaceTopography as st

    from core.geometry.heightmap import read_topography

    path = tmp_path / "bowl.nc"
    st.Topography(np.arange(64.0).reshape(8, 8), (1.0, 1.0)).to_netcdf(str(path))
    from_path, from_bytes = read_topography(path), read_topography(io.BytesIO(path.read_bytes()))
    assert np.array_equal(from_path.heights(), from_bytes.heights()) and from_bytes.nb_grid_pts == (8, 8)
    with pytest.raises(ValueError, match="^file not found: "):
        read_topography(tmp_path / "nope.nc")
    with pytest.raises(ValueError, match="^the upload is in no format that can be read; the readable formats: "):
        read_topography(io.BytesIO(b"\x00\x01 nothing"), name="the upload")


def test_height_map_runs_under_the_normal_history():
    """Under an oscillating normal force the contact grows beyond its nominal size: the run's grid covers the
    contact under the largest load (it refused any load above the nominal one, so the explorer's height map under
    the 'normal' loading showed INVALID INPUT at its default amplitude). The sphere's gap sampled at a/10 runs as
    the sphere under the same history, each step's bound carrying that step's load."""
    m = _map(lambda r2, X, Y: 0.375 * r2, n=31)
    r = core.simulate_cycles(0.3, 0.3, periods=2, body=m, history="normal", amplitude=0.5)
    s = core.simulate_cycles(0.3, 0.3, periods=2, dx=0.1, body="sphere", history="normal", amplitude=0.5)
    nominal = core.simulate_cycles(0.3, 0.3, periods=2, body=m)
    assert r.y_edges.size > nominal.y_edges.size, "the grid grows with the largest load"
    np.testing.assert_allclose(r.increment_per_period, s.increment_per_period, rtol=1e-5, atol=1e-9)
    carried = np.array([r.pressure_at(k).sum() * r.dx**2 for k in range(r.xc.size)])
    np.testing.assert_allclose(carried, r.P * r.body.total_load, rtol=1e-6, err_msg="load of every step")
    with pytest.raises(ValueError, match="edge"):  # a load whose contact leaves the map is refused by name
        core.simulate_cycles(0.05, 0.3, periods=2, body=_map(lambda r2, X, Y: 0.375 * r2, n=25), history="normal",
                             amplitude=0.9)
