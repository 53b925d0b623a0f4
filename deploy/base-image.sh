#!/usr/bin/env bash
# Prints the name of a local Debian 12 (bookworm) image for podman, making
# one with debootstrap when none is present, so no registry is needed.
#
#   deploy/base-image.sh [PREFERRED_IMAGE...]
# The first of PREFERRED_IMAGE… that exists locally (e.g. a pulled
# debian:bookworm-slim), else the cached localhost/armature-bookworm:debootstrap,
# else a minbase bookworm debootstrapped from the Debian mirror apt already
# uses here and imported under that name. Progress goes to stderr, the
# image name to stdout.
set -euo pipefail

for candidate in "$@" localhost/armature-bookworm:debootstrap; do
  if podman image exists "$candidate"; then
    echo "$candidate"
    exit 0
  fi
done

image=localhost/armature-bookworm:debootstrap
command -v debootstrap >/dev/null || { echo "base-image: debootstrap is not installed (apt-get install debootstrap)" >&2; exit 1; }
sudo=""
[[ $(id -u) -ne 0 ]] && sudo="sudo"

# The Debian mirror apt uses here (deb822 URIs: or one-line deb entries), not the security one.
mirror=$(cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources 2>/dev/null |
  grep -oE '(https?)://[^ ]+/debian/?( |$)' | grep -v security | head -n1 | tr -d ' ' || true)
mirror=${mirror:-http://deb.debian.org/debian}

rootfs=$(mktemp -d /var/tmp/armature-rootfs.XXXXXX)
trap '$sudo rm -rf "$rootfs"' EXIT
echo "base-image: debootstrap bookworm (minbase) from $mirror" >&2
$sudo debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >&2
# As the official image: updates and security sources, no apt caches, no recommends.
security=${mirror%/debian*}/debian-security
$sudo rm -f "$rootfs/etc/apt/sources.list"
$sudo tee "$rootfs/etc/apt/sources.list.d/debian.sources" >/dev/null <<SOURCES
Types: deb
URIs: $mirror
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: $security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
echo 'APT::Install-Recommends "false";' | $sudo tee "$rootfs/etc/apt/apt.conf.d/90armature-no-recommends" >/dev/null
$sudo rm -rf "$rootfs"/var/lib/apt/lists/* "$rootfs"/var/cache/apt/archives/*.deb "$rootfs"/var/cache/apt/*.bin
$sudo tar -C "$rootfs" -c . | podman import --change 'CMD ["bash"]' - "$image" >&2
echo "$image"
