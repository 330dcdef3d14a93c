#!/usr/bin/env bash
# Installs everything the build and the tests need on a Debian 12 machine (run as root) and fetches
# MeshLab's headers + vcglib from Debian's `meshlab` source package into .deps/ (git-ignored).
# Quick and quiet when everything is already there.
set -euo pipefail

top=$(cd "$(dirname "$0")/.." && pwd)
deps="$top/.deps"
ml_version="2020.09+dfsg1-2"
ml_dir="$deps/meshlab-2020.09"

packages=(build-essential cmake dpkg-dev meshlab qtbase5-dev libqt5opengl5-dev libeigen3-dev
          libglew-dev libgtest-dev xvfb xauth xdotool imagemagick python3-numpy)
# A caller's own packages, installed with these (bench/prepare.sh): `setup.sh [PACKAGE ...]`.
packages+=("$@")

log() { echo "[setup] $*" >&2; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@";
  else log "need root for: $*"; exit 1; fi
}

apt_updated=0
apt_update() {
  if [ $apt_updated -eq 0 ]; then
    # Unrelated third-party lists may be unreachable here; Debian's own must work.
    as_root apt-get update -qq >/dev/null 2>&1 || as_root apt-get update -qq || true
    apt_updated=1
  fi
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing Debian packages: ${missing[*]}"
  apt_update
  as_root env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 install -y -qq \
    --no-install-recommends "${missing[@]}" >/dev/null
fi

installed=$(dpkg-query -W -f='${Version}' meshlab)
if [ "$installed" != "$ml_version" ]; then
  log "warning: installed meshlab is $installed, headers are fetched for $ml_version"
fi

if [ ! -f "$ml_dir/src/common/interfaces.h" ] || [ ! -d "$ml_dir/vcglib/vcg" ]; then
  if ! grep -rqsE '^(Types:.*deb-src|deb-src )' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    log "adding a deb-src entry for bookworm"
    uris=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
    [ -n "$uris" ] || uris="http://deb.debian.org/debian"
    as_root tee /etc/apt/sources.list.d/meshlab-plugin-src.sources >/dev/null <<SRC
Types: deb-src
URIs: $uris
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
    apt_updated=0
  fi
  apt_update
  log "fetching the meshlab $ml_version source package"
  tmp="$deps/download"
  rm -rf "$tmp" && mkdir -p "$tmp"
  (cd "$tmp" && apt-get source -qq --download-only "meshlab=$ml_version" >/dev/null 2>&1)
  dsc=$(ls "$tmp"/meshlab_*.dsc | head -1)
  rm -rf "$ml_dir"
  dpkg-source --no-check -x "$dsc" "$ml_dir" >/dev/null
  rm -rf "$tmp"
  [ -f "$ml_dir/src/common/interfaces.h" ] || { log "meshlab sources unpacked without src/common"; exit 1; }
fi
