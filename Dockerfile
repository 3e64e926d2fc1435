# The Shakedown Explorer, served by Panel on port 5006.
#   docker build -t shakedown-explorer .
#   docker run --rm -p 5006:5006 shakedown-explorer    # then open http://localhost:5006/main
FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    NUMBA_CACHE_DIR=/var/cache/shakedown/numba

WORKDIR /srv/shakedown
COPY pyproject.toml README.md ./
COPY core ./core
COPY app ./app

# install the project, then compile the solver once so the first visitor does not wait for numba
RUN pip install --no-cache-dir . \
    && useradd --system --create-home --uid 10001 shakedown \
    && mkdir -p "$NUMBA_CACHE_DIR" \
    && python -c "import core; [core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, kernel=k, L_over_a=10.0 if k == 'strip' else None) for k in ('plane', 'strip')]" \
    && chown -R shakedown "$NUMBA_CACHE_DIR"

USER 10001
EXPOSE 5006
# building a page holds the server's event loop (about 1.5 s a session): when a whole class opens
# the app at once /liveness can wait tens of seconds, which is busy, not dead (benchmarks/loadtest.py)
HEALTHCHECK --interval=30s --timeout=30s --start-period=60s --retries=5 \
    CMD ["python", "-c", "import sys, urllib.request; sys.exit(urllib.request.urlopen('http://127.0.0.1:5006/liveness', timeout=29).status != 200)"]
CMD ["panel", "serve", "app/main.py", "--address", "0.0.0.0", "--port", "5006", "--liveness", "--unused-session-lifetime", "120000", "--allow-websocket-origin=*"]
