#!/usr/bin/env bash
# Prepares the PyMeshLab side of the project on a Debian 12 machine (run as root):
#  - a venv at .venv with pymeshlab==2025.7.post1 (bundles MeshLab 2025.07, double precision),
#    pytest and numpy;
#  - MeshLab 2025.07's src/common and src/vcglib in .deps/meshlab-2025.07 (git-ignored), taken from
#    the orig tarball of Debian unstable's `meshlab 2025.07~dfsg-4` source package, so that a
#    2025.07-API plugin can be compiled against exactly the headers the wheel was built from.
# Debian unstable is added as a deb-src entry only: no binaries from sid ever reach this machine.
# Idempotent; quick and quiet when everything is already there. See docs/PYMESHLAB_NOTES.md.
set -euo pipefail

top=$(cd "$(dirname "$0")/.." && pwd)
venv="$top/.venv"
deps="$top/.deps"
ml_dir="$deps/meshlab-2025.07"
ml_src_version="2025.07~dfsg-4"
orig_name="meshlab_2025.07~dfsg.orig.tar.xz"
orig_sha256="d22c98d362f2a284e481af8dbfc272b2222f5b9c67b3cf8bec57d1c3161886f4"
pymeshlab_version="2025.7.post1"
python="${PYTHON:-/usr/bin/python3}"
sid_list=/etc/apt/sources.list.d/meshlab-plugin-src-sid.sources

log() { echo "[setup_pymeshlab] $*" >&2; }
die() { log "error: $*"; exit 1; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@";
  else die "need root for: $*"; fi
}

apt_update() {
  # Unrelated third-party lists may be unreachable here; Debian's own must work.
  as_root apt-get update -qq >/dev/null 2>&1 || as_root apt-get update -qq || true
}

apt_install() {
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    log "installing Debian packages: ${missing[*]}"
    apt_update
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      "${missing[@]}" >/dev/null || die "apt-get install ${missing[*]} failed"
  fi
}

# ---- 1. the venv ------------------------------------------------------------------------------
[ -x "$python" ] || python=$(command -v python3) || die "no python3 found"
if [ ! -x "$venv/bin/python" ]; then
  "$python" -c 'import ensurepip, venv' 2>/dev/null || apt_install python3-venv
  log "creating $venv"
  "$python" -m venv "$venv" || die "python3 -m venv $venv failed"
fi
if ! "$venv/bin/python" - "$pymeshlab_version" 2>/dev/null <<'PY'
import sys
from importlib.metadata import version
assert version("pymeshlab") == sys.argv[1]
import pytest, numpy  # noqa: F401
PY
then
  log "installing pymeshlab==$pymeshlab_version, pytest, numpy into $venv"
  "$venv/bin/pip" install -q "pymeshlab==$pymeshlab_version" pytest numpy \
    || die "pip install into $venv failed"
fi

# ---- 2. MeshLab 2025.07 headers + vcglib --------------------------------------------------------
have_tree() {
  [ -f "$ml_dir/src/common/plugins/interfaces/filter_plugin.h" ] &&
  [ -f "$ml_dir/src/vcglib/vcg/complex/complex.h" ]
}

if ! have_tree; then
  apt_install dpkg-dev xz-utils ca-certificates
  orig="$deps/$orig_name"
  if [ ! -f "$orig" ] || ! echo "$orig_sha256  $orig" | sha256sum -c --status; then
    if ! grep -rlsE '^Suites:.*\bsid\b' /etc/apt/sources.list.d/ | xargs -r grep -qs '^Types:.*deb-src' &&
       ! grep -qsE '^deb-src .* sid ' /etc/apt/sources.list; then
      log "adding a deb-src (source only) entry for Debian unstable: $sid_list"
      uris=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
      [ -n "$uris" ] || uris="http://deb.debian.org/debian"
      as_root tee "$sid_list" >/dev/null <<SRC
Types: deb-src
URIs: $uris
Suites: sid
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
    fi
    apt_update
    log "downloading the meshlab $ml_src_version orig tarball"
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    # The index may be older than the mirror, so the .dsc/.debian.tar.xz can 404: only the orig
    # tarball matters, and its checksum decides.
    (cd "$tmp" && apt-get source -qq --download-only "meshlab=$ml_src_version" >/dev/null 2>&1) || true
    [ -f "$tmp/$orig_name" ] ||
      die "apt-get source --download-only meshlab=$ml_src_version did not fetch $orig_name (is the sid deb-src entry in $sid_list usable? try: apt-cache showsrc meshlab)"
    echo "$orig_sha256  $tmp/$orig_name" | sha256sum -c --status ||
      die "$orig_name has sha256 $(sha256sum "$tmp/$orig_name" | cut -d' ' -f1), expected $orig_sha256"
    mkdir -p "$deps"
    mv "$tmp/$orig_name" "$orig"
  fi
  log "unpacking src/common and src/vcglib into $ml_dir"
  # The tarball holds one directory, meshlab-<git sha>/; the plugin needs only src/common (headers),
  # src/vcglib and ML_VERSION. (No `tar | head`: under pipefail its SIGPIPE would abort the script.)
  top_dir=$(tar -tJf "$orig" | awk -F/ 'NR == 1 {print $1}')
  [ -n "$top_dir" ] || die "$orig is not a readable tar.xz"
  unpack=$(mktemp -d "$deps/unpack.XXXXXX")
  tar -xJf "$orig" -C "$unpack" "$top_dir/ML_VERSION" "$top_dir/LICENSE.txt" \
      "$top_dir/src/common" "$top_dir/src/vcglib" ||
    { rm -rf "$unpack"; die "could not unpack src/common and src/vcglib from $orig"; }
  rm -rf "$ml_dir"
  mv "$unpack/$top_dir" "$ml_dir"
  rm -rf "$unpack"
  have_tree || die "$ml_dir lacks src/common/plugins/interfaces/filter_plugin.h or src/vcglib"
fi
