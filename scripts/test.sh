#!/usr/bin/env bash
# Install everything the test suite needs on a fresh machine, then run all of it.
# Used as is by the README and by CI (.ci/run, in a virtual environment of its own). The test extras include
# the docs extra: the suite builds the documentation with warnings as errors (tests/test_docs.py) and runs the
# docstring examples of core.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v chromium >/dev/null 2>&1; then   # browser tests drive Debian's Chromium
  echo "test.sh: installing Debian's chromium for the browser tests (apt-get)"
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq chromium >/dev/null
fi
echo "test.sh: installing the package and its test extras into $(python -c 'import sys; print(sys.prefix)')" \
     "(pip's progress follows; a fresh environment takes a few minutes)"
start=$SECONDS
python -m pip install --disable-pip-version-check --progress-bar on -e ".[test]"
# Two workers (pytest-xdist), an idle one taking tests from the other's queue (worksteal): a browser test mostly
# waits (for the served app, for Chromium, for a solve), so two at once use the two cores of a small machine
# (measured on 2 cores: 2141 s of tests in 1040 s; a file per worker, loadfile, 1106-1140 s; 3 workers no better).
# SHAKEDOWN_TEST_WORKERS=0 runs everything in this process (one test, a debugger).
WORKERS="${SHAKEDOWN_TEST_WORKERS:-2}"
echo "test.sh: installed in $((SECONDS - start)) s; running the test suite on $WORKERS workers" \
     "(python -m pytest -n $WORKERS --dist worksteal $*)"
exec python -m pytest -n "$WORKERS" --dist worksteal "$@"
