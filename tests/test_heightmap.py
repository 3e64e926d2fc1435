"""Bodies from sampled surfaces (core/heightmap.py): a line profile on the 1D engine, a height map's limit."""

import numpy as np
import pytest

import core
from core.heightmap import HeightMap, HeightProfile
from core.punch import punch_profile


def test_sampled_cylinder_is_the_cylinder():
    x = np.linspace(-2, 2, 1601)
    body = HeightProfile((2 / np.pi) * x**2, x[1] - x[0])
    for w in (0.1, 0.5):
        assert float(core.ft_limit(w, body=body)) == pytest.approx(float(core.ft_limit(w)), abs=5e-5)
    r = core.simulate_cycles(0.5, 0.3, periods=8, body=body)
    ref = core.simulate_cycles(0.5, 0.3, periods=8)
    assert np.allclose(r.increment_per_period, ref.increment_per_period, rtol=2e-3, atol=1e-6)
    assert r.body == "heightmap" and r.body_spec == body


def test_measured_punch_from_a_surfacetopography_file(tmp_path):
    """A punch's profile as a 'measured' line scan in micrometres (a = 200 um, P/E* = 0.05 um), written to a
    NetCDF file and read back: its limit is the punch's, and runs 10 % either side of it shake down / ratchet."""
    st = pytest.importorskip("SurfaceTopography")
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
    st = pytest.importorskip("SurfaceTopography")
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
