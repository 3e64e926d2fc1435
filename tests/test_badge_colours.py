"""The verdict badge's three regimes read apart in greyscale and for colour-blind viewers (issue 30, item 3):
the colours' lightness, contrast and colour differences, computed from app.styles.BADGE_COLORS."""

import itertools
import re

import pytest

from app import styles
from app.styles import BADGE_COLORS, colour_report, contrast_ratio, lightness, relative_luminance
from core.records.verdict import REGIMES

#: Lightness difference (CIE L*) two badges keep at least: apart in a greyscale print or a dim projector.
MIN_DL = 20.0
#: Colour difference (CIE76 ΔE) two badges keep at least for every vision (normal, protan, deutan, tritan).
MIN_DE = 40.0


def test_luminance_and_contrast_match_their_definitions():
    """WCAG 2's values of known colours: white 1, black 0, their ratio 21; Okabe and Ito's blue 0.153."""
    assert relative_luminance("white") == pytest.approx(1.0) and relative_luminance("black") == 0.0
    assert contrast_ratio("#ffffff", "#000000") == pytest.approx(21.0)
    assert contrast_ratio("#0072B2", "#0072B2") == pytest.approx(1.0)
    assert relative_luminance("#0072B2") == pytest.approx(0.1525, abs=5e-4)
    assert lightness("#ffffff") == pytest.approx(100.0, abs=0.01) and lightness("#000000") == pytest.approx(0.0)
    assert lightness("#777777") == pytest.approx(50.0, abs=0.5)  # mid grey
    for bad in ("red", "#12345", "#gggggg", None):
        with pytest.raises(ValueError, match="colour"):
            relative_luminance(bad)
    with pytest.raises(ValueError, match="vision"):
        styles.colour_difference("#000000", "#ffffff", "monochrome")


def test_a_colour_blind_viewer_loses_red_green_but_not_lightness():
    """The simulation does what it is for: red and green, far apart for normal vision, come close for a protan or
    deutan viewer, and blue and yellow stay apart for them."""
    red, green = "#FF0000", "#00FF00"
    assert styles.colour_difference(red, green) > 80
    for vision in ("protan", "deutan"):
        assert styles.colour_difference(red, green, vision) < 0.5 * styles.colour_difference(red, green), vision
    assert styles.colour_difference("#0072B2", "#F0E442", "protan") > 80


def test_every_regime_has_a_badge_colour():
    assert set(BADGE_COLORS) == set(REGIMES)


def test_the_three_regimes_read_apart_in_greyscale_and_for_colour_blind_viewers():
    """Any two badges differ by MIN_DL in lightness and by MIN_DE in colour for normal, protan, deutan and tritan
    vision; the text on each has a contrast of at least 4.5:1 (WCAG AA)."""
    report = colour_report()
    assert len(report["pairs"]) == len(list(itertools.combinations(BADGE_COLORS, 2)))
    for (a, b), pair in report["pairs"].items():
        assert pair["dL"] >= MIN_DL, (a, b, pair)
        for vision in ("normal", "protan", "deutan", "tritan"):
            assert pair[vision] >= MIN_DE, (a, b, vision, pair)
        # in greyscale the lighter of two differs visibly in luminance too
        assert pair["contrast"] >= 1.8, (a, b, pair)
    for regime, ratio in report["text"].items():
        assert ratio >= 4.5, (regime, ratio)


def test_the_badge_css_takes_its_colours_from_badge_colors():
    """One declaration of the colours: the style sheet's rule of each regime is BADGE_COLORS' background and text."""
    for regime, (bg, fg) in BADGE_COLORS.items():
        css = re.sub(r"[^a-z]", "", regime)
        rule = re.search(rf"\.regime-{css} \{{background: ([^;]+); color: ([^;]+);\}}", styles.CSS)
        assert rule is not None and rule.groups() == (bg, fg), regime
