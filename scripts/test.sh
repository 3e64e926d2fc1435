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
echo "test.sh: installed in $((SECONDS - start)) s; running the test suite (python -m pytest $*)"
exec python -m pytest "$@"
