# Convenience targets; the canonical commands are scripts/serve.sh and
# scripts/test.sh (see README).

VENV          ?= .venv
PYTHON        ?= $(VENV)/bin/python
IMAGE         ?= peshkin-service
LOCAL_BASE    ?= localhost/peshkin-base:bookworm
PODMAN        ?= podman
PODMAN_BUILD_FLAGS ?=
# Host CA bundle handed to pip inside the build (read-only mount, not copied
# into the image), so builds work behind a TLS-intercepting proxy too.
# Set HOST_CA_BUNDLE= (empty) to disable.
HOST_CA_BUNDLE ?= $(wildcard /etc/ssl/certs/ca-certificates.crt)
CA_BUILD_FLAGS = $(if $(HOST_CA_BUNDLE),-v $(HOST_CA_BUNDLE):/run/host-ca-bundle.crt:ro --build-arg PIP_CERT=/run/host-ca-bundle.crt)
PORT          ?= 8000
SMOKE_PORT    ?= 18000

.PHONY: help venv serve test test-fast openapi bench load load-mixed docker-local-base docker-local docker-smoke docker-run-local

help:
	@echo "make serve             run the service (bash scripts/serve.sh)"
	@echo "make test              run the whole test suite (bash scripts/test.sh; what CI runs)"
	@echo "make test-fast         the everyday tier: tests not marked slow, two workers"
	@echo "make openapi           write the OpenAPI document (scripts/gen_openapi.py)"
	@echo "make bench             run the benchmarks (tests/benchmarks)"
	@echo "make load              load test on loopback with wrk (scripts/load/run.py)"
	@echo "make load-mixed        issue 35's mixed load, then with hostile bodies (scripts/load/mixed.py)"
	@echo "make docker-local-base debootstrap a Debian base image into podman ($(LOCAL_BASE))"
	@echo "make docker-local      podman build $(IMAGE) on that base (no dangling image left)"
	@echo "make docker-smoke      build, start, send every documented example, stop; size and cold start"
	@echo "make docker-run-local  podman run --stop-timeout 40 $(IMAGE) on port $(PORT)"

serve:
	bash scripts/serve.sh

test:
	bash scripts/test.sh

test-fast:
	bash scripts/test.sh --fast

# Create/refresh .venv with the dev requirements (instant when up to date).
venv:
	@bash scripts/test.sh --version >/dev/null

openapi: venv
	$(PYTHON) scripts/gen_openapi.py

bench: venv
	$(PYTHON) -m pytest tests/benchmarks -q --run-benchmarks

load: venv
	$(PYTHON) scripts/load/run.py

load-mixed: venv
	$(PYTHON) scripts/load/mixed.py --write
	$(PYTHON) scripts/load/mixed.py --write --bodies

docker-local-base:
	bash scripts/docker-local-base.sh $(LOCAL_BASE)

# --format docker keeps the HEALTHCHECK (the OCI format drops it). --layers=false: no
# image per step and none of the builder stage (with layers podman keeps the builder's
# 1.2 GB venv as an untagged image); then the previous build's image, untagged once the
# tag moved, is pruned (by the Dockerfile's label: no other image is touched).
docker-local:
	$(PODMAN) build --layers=false --format docker $(CA_BUILD_FLAGS) $(PODMAN_BUILD_FLAGS) \
		--build-arg BASE_IMAGE=$(LOCAL_BASE) -t $(IMAGE) .
	$(PODMAN) image prune --force --filter label=io.peshkin.image=service

# Build, then start the image, time its cold start, send every documented example, stop.
docker-smoke: docker-local venv
	$(PYTHON) scripts/image/smoke.py $(IMAGE) $(SMOKE_PORT)

docker-run-local:
	$(PODMAN) run --rm --runtime runc --stop-timeout 40 --ulimit nofile=1024:1024 --ulimit nproc=4096:4096 \
		-p $(PORT):8000 $(IMAGE)
