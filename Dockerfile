# syntax=docker/dockerfile:1
#
# Planning service image.
#   docker build -t peshkin-service .
#   docker run -p 8000:8000 peshkin-service
#
# BASE_IMAGE must be a Debian-like image with Python 3.11 reachable as
# `python3` (with the venv module): the official python:3.11-slim, or the
# debootstrapped local base from scripts/docker-local-base.sh.
ARG BASE_IMAGE=python:3.11-slim

# ---------------------------------------------------------------- builder --
FROM ${BASE_IMAGE} AS builder

# Optional: path of a CA bundle pip should trust, for builds behind a
# TLS-intercepting proxy.  Mount the file into the build and pass its path
# (the Makefile's docker-local target does this with the host's bundle).
# Unset by default; nothing of it ends up in the final image.
ARG PIP_CERT

ENV PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    PYTHONDONTWRITEBYTECODE=1

RUN python3 -c 'import sys; assert sys.version_info[:2] == (3, 11), sys.version' \
 && python3 -m venv /opt/venv \
 && /opt/venv/bin/python -m pip install --quiet --upgrade pip

COPY requirements.txt /tmp/requirements.txt
RUN /opt/venv/bin/python -m pip install --quiet -r /tmp/requirements.txt \
 && /opt/venv/bin/python -c 'import importlib.util as u, sys; sys.exit(u.find_spec("highspy") is not None)'

# Slim the venv: scripts/image/slim-venv.sh says what goes and why each removal is safe
# (the service never loads it); its step before the last imports the app and runs a small
# solve with each back end (scripts/image/pyc_keep.py), so a removal that breaks one fails
# the build; stripping and Ray are checked by `make docker-smoke` on the built image.
# binutils: strip. SLIM_STEPS (default: every step) picks steps, to measure them one by one.
RUN apt-get update -qq \
 && DEBIAN_FRONTEND=noninteractive apt-get install -qq -y --no-install-recommends binutils >/dev/null
COPY . /src
ARG SLIM_STEPS=""
# WITH_RAY=false: an image without Ray (feeder catalogues one design after the other)
ARG WITH_RAY=true
RUN SLIM_STEPS="${SLIM_STEPS}" WITH_RAY="${WITH_RAY}" bash /src/scripts/image/slim-venv.sh /opt/venv /src

# ------------------------------------------------------------------ final --
FROM ${BASE_IMAGE}

# `make docker-local` prunes the untagged images with this label (the previous build's
# image once the tag moves to the new one), and no other.
LABEL io.peshkin.image=service

# HOME: Ray keeps a local cluster's token in $HOME/.ray, and the app user's /app is read-only.
ENV PATH=/opt/venv/bin:${PATH} \
    PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    MPLBACKEND=Agg \
    MPLCONFIGDIR=/tmp/matplotlib \
    HOME=/tmp \
    RAY_USAGE_STATS_ENABLED=0

RUN groupadd --gid 10001 app \
 && useradd --uid 10001 --gid app --no-create-home --home-dir /app --shell /usr/sbin/nologin app

COPY --from=builder /opt/venv /opt/venv
WORKDIR /app
COPY --chown=root:root . /app
# The service's own bytecode: /app is read-only to the app user, so without it every
# process (web workers, their forkservers) compiles the service's modules at each start.
# unchecked-hash: valid whatever the build does to the files' mtimes (slim-venv.sh).
RUN python3 -m compileall -q -j 0 --invalidation-mode unchecked-hash service solver models
# The solver's compiled kernels (numba, solver/kernels/): compiled here into numba's cache
# beside the sources, for a generic x86_64 CPU so that the cache is valid wherever the image
# runs; the service copies it to a writable folder at start (numba reads only a cache it
# could write) and no request pays for a compile.
ENV NUMBA_CPU_NAME=generic
RUN python3 -m solver.kernels

USER app
EXPOSE 8000

HEALTHCHECK --interval=30s --timeout=5s --start-period=60s --retries=3 \
  CMD ["python3", "-c", "import sys, urllib.request; sys.exit(0 if urllib.request.urlopen('http://127.0.0.1:8000/healthz', timeout=4).status == 200 else 1)"]

# Same start command as `bash scripts/serve.sh` (gunicorn supervising the web processes,
# service/server.py), listening on all interfaces; tune with PESHKIN_* (service/settings.py).
ENV PESHKIN_HOST=0.0.0.0 PESHKIN_PORT=8000
CMD ["python3", "-m", "service"]
