# The Shakedown Explorer, served by Panel on port 5006.
#   docker build -t shakedown-explorer .
#   docker run --rm -p 5006:5006 --read-only --tmpfs /tmp shakedown-explorer   # then open http://localhost:5006/main
# Served under another host name or port, allow its websocket origin:
#   docker run ... -e BOKEH_ALLOW_WS_ORIGIN=class.example.org,class.example.org:443 shakedown-explorer
# Solves on a Dask cluster (README "Serving it to a class"): the same image runs the workers,
#   docker run ... shakedown-explorer dask worker tcp://scheduler:8786 --nthreads 1
#   docker run ... -e SHAKEDOWN_SCHEDULER=tcp://scheduler:8786 shakedown-explorer
# Any user id works (docker run --user 12345): nothing is written outside /tmp.
FROM python:3.11.10-slim-bookworm

# SHAKEDOWN_NUMBA_CACHE_SEED: the solver compiled at build time for the installed package (read-only);
# app/health.py copies it to NUMBA_CACHE_DIR, on the /tmp tmpfs, at start: numba needs to write there.
ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    HOME=/tmp \
    SHAKEDOWN_NUMBA_CACHE_SEED=/opt/shakedown/numba-cache \
    NUMBA_CACHE_DIR=/tmp/numba-cache \
    BOKEH_ALLOW_WS_ORIGIN=localhost:5006,127.0.0.1:5006

# the code is held once: installed in site-packages, the sources removed
WORKDIR /tmp/src
COPY pyproject.toml README.md ./
COPY core ./core
COPY app ./app
RUN pip install --no-cache-dir "./[dask]" && rm -rf /tmp/src

# compile the solver for the installed copy, the one `panel serve` and the Dask workers import
# (numba caches per source path), away from any source tree, into the seed readable by any user id
WORKDIR /srv/shakedown
RUN NUMBA_CACHE_DIR="$SHAKEDOWN_NUMBA_CACHE_SEED" python -c "import app.runs as r, core; assert 'site-packages' in core.__file__; r.backend().warm()" \
    && chmod -R a+rX "$SHAKEDOWN_NUMBA_CACHE_SEED" \
    && ln -s "$(python -c 'import app, os; print(os.path.dirname(app.__file__))')" app

USER 10001
EXPOSE 5006
# /liveness answers 200 once the solver is warm (app/health.py); a session's build holds the event loop
# for a while, so a whole class opening the app at once can delay it: busy, not dead (benchmarks/loadtest.py)
HEALTHCHECK --interval=30s --timeout=30s --start-period=120s --retries=5 \
    CMD ["python", "-c", "import sys, urllib.request; sys.exit(urllib.request.urlopen('http://127.0.0.1:5006/liveness', timeout=29).status != 200)"]
CMD ["panel", "serve", "app/main.py", "--address", "0.0.0.0", "--port", "5006", "--plugins", "app.health", "--unused-session-lifetime", "120000"]
