#!/usr/bin/env bash
# Build a minimal Debian bookworm base image with Python 3.11 into podman,
# for building the Dockerfile where no registry base image can be pulled:
#
#   sudo bash scripts/docker-local-base.sh            # -> localhost/peshkin-base:bookworm
#   podman build --build-arg BASE_IMAGE=localhost/peshkin-base:bookworm -t peshkin-service .
#
# Needs root, debootstrap and podman (Debian: apt-get install debootstrap podman).
# DEBIAN_MIRROR overrides debootstrap's default mirror.
set -euo pipefail

TAG="${1:-localhost/peshkin-base:bookworm}"
SUITE="${SUITE:-bookworm}"
PACKAGES="python3.11,python3.11-venv,python3-pip,ca-certificates"

die() { echo "docker-local-base.sh: $*" >&2; exit 1; }

[[ "$(id -u)" -eq 0 ]] || die "must run as root (debootstrap needs it)"
command -v debootstrap >/dev/null || die "debootstrap not found (apt-get install debootstrap)"
command -v podman >/dev/null || die "podman not found (apt-get install podman)"

workdir="$(mktemp -d "${TMPDIR:-/tmp}/peshkin-base.XXXXXX")"
trap 'rm -rf "$workdir"' EXIT
rootfs="$workdir/rootfs"

mirror_args=()
[[ -n "${DEBIAN_MIRROR:-}" ]] && mirror_args=("$DEBIAN_MIRROR")

echo "docker-local-base.sh: debootstrapping $SUITE into $rootfs" >&2
debootstrap --variant=minbase --include="$PACKAGES" "$SUITE" "$rootfs" "${mirror_args[@]}"

# Trim what an image does not need.
chroot "$rootfs" apt-get clean
rm -rf "$rootfs"/var/lib/apt/lists/* "$rootfs"/var/cache/apt/*.bin \
       "$rootfs"/usr/share/doc/* "$rootfs"/usr/share/man/* "$rootfs"/tmp/*
# Python 3.11 as `python3` (and `python`, like the official images).
ln -sf python3.11 "$rootfs/usr/bin/python3"
[[ -e "$rootfs/usr/bin/python" ]] || ln -s python3 "$rootfs/usr/bin/python"

chroot "$rootfs" python3 -c 'import sys, venv, ensurepip; assert sys.version_info[:2] == (3, 11)'

echo "docker-local-base.sh: importing as $TAG" >&2
tar --numeric-owner -C "$rootfs" -c . |
    podman import \
        --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
        --change 'ENV LANG=C.UTF-8' \
        --change 'CMD ["python3"]' \
        - "$TAG"

podman image inspect --format '{{.Id}} {{.Size}}' "$TAG"
