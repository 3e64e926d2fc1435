"""The browser tests' harness (app/serving.py) fails at once, saying why, when the server or the browser cannot
start: it does not wait out its timeouts (issue 29: two browser tests waited 180 s each on a fresh machine)."""

import pytest

from app import serving


def test_a_server_that_exits_is_reported_at_once_with_its_output():
    """``panel serve`` refusing an option exits at once: served_app raises ServerExited (not the TimeoutError of
    its 420 s wait) with the exit status and the server's own words."""
    with pytest.raises(serving.ServerExited) as caught:
        with serving.served_app(extra_args=["--no-such-option"]):
            pass
    message = str(caught.value)
    assert "exited with status 2" in message and "--no-such-option" in message, message


def test_a_missing_browser_is_reported_at_once(monkeypatch, tmp_path):
    monkeypatch.setattr(serving, "CHROMIUM", str(tmp_path / "no-chromium"))
    with pytest.raises(RuntimeError, match="no Chromium at .*no-chromium.*apt-get install chromium"):
        with serving.chromium():
            pass


def test_a_browser_that_cannot_start_is_reported(monkeypatch, tmp_path):
    """An executable that is not a browser: Playwright's launch error, as a RuntimeError naming the executable."""
    fake = tmp_path / "chromium"
    fake.write_text("#!/bin/sh\necho 'not a browser' >&2\nexit 3\n")
    fake.chmod(0o755)
    monkeypatch.setattr(serving, "CHROMIUM", str(fake))
    with pytest.raises(RuntimeError, match=f"Chromium \\({fake}\\) did not start"):
        with serving.chromium():
            pass


def test_wait_until_gives_up_on_request_and_names_the_last_error():
    calls = []

    def boom():
        calls.append(1)
        raise serving.ServerExited("gone")

    with pytest.raises(serving.ServerExited, match="gone"):
        serving.wait_until(boom, timeout=30, give_up=serving.ServerExited)
    assert len(calls) == 1
    with pytest.raises(TimeoutError, match="ValueError"):
        serving.wait_until(lambda: int("x"), timeout=0.2)
