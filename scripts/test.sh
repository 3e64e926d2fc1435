#!/usr/bin/env bash
# Install everything the test suite needs on a fresh machine, then run all of it.
# Used as is by the README and by CI (.ci/run). The test extras include the docs extra: the suite builds
# the documentation with warnings as errors (tests/test_docs.py) and runs the docstring examples of core.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v chromium >/dev/null 2>&1; then   # browser tests drive Debian's Chromium
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq chromium >/dev/null
fi
python -m pip install -q --disable-pip-version-check -e ".[test]"
exec python -m pytest "$@"
