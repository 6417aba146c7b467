#!/usr/bin/env bash
# Fetches the real test volumes from Debian packages (apt-get download + dpkg -x) into
# <repo>/.cache/volumes/ (git-ignored). Files already there are skipped, so a second run
# needs no network. Needs no root (apt-get download works as any user once the package
# lists exist; as root, `apt-get update` is run when a package is not known yet).
#
#   mricron-data     -> ch2.nii.gz (Colin27 T1, 181x217x181 uint8), aal.nii.gz, brodmann.nii.gz,
#                       aal.nii.txt (the AAL labels: "<value> <name> <code>" per line)
#   libvolpack1-dev  -> brainsmall.den (VolPack MRI head, 128x128x84 uint8), denfile.c
#   python3-dipy     -> small_64D.nii (10x10x10 x 65 diffusion volumes)
#
#   MCV_DATA_DIR=/some/dir  fetch there instead
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
dest="${MCV_DATA_DIR:-$repo/.cache/volumes}"
mkdir -p "$dest"

# package | path inside the package | file name in $dest
entries=(
  "mricron-data|usr/share/mricron/templates/ch2.nii.gz|ch2.nii.gz"
  "mricron-data|usr/share/mricron/templates/aal.nii.gz|aal.nii.gz"
  "mricron-data|usr/share/mricron/templates/brodmann.nii.gz|brodmann.nii.gz"
  "mricron-data|usr/share/mricron/templates/aal.nii.txt|aal.nii.txt"
  "libvolpack1-dev|usr/share/doc/libvolpack1-dev/examples/brainsmall.den|brainsmall.den"
  "libvolpack1-dev|usr/share/doc/libvolpack1-dev/examples/denfile.c|denfile.c"
  "python3-dipy|usr/lib/python3/dist-packages/dipy/data/files/small_64D.nii|small_64D.nii"
)

work=""
# An if, not `[ ... ] &&`: with nothing downloaded the test fails, and an EXIT trap's status
# becomes the script's (it made a run with every volume present exit 1).
cleanup() { if [ -n "$work" ]; then rm -rf "$work"; fi; }
trap cleanup EXIT

updated=0
declare -A extracted=()
declare -A unavailable=()
failed=0

extract_package() { # $1 = package; sets extracted[$1] to the folder it was unpacked into
  local pkg="$1"
  [ -n "${extracted[$pkg]:-}" ] && return 0
  [ -n "${unavailable[$pkg]:-}" ] && return 1 # already reported
  if [ -z "$work" ]; then
    work="$(mktemp -d "${TMPDIR:-/tmp}/mcv-fetch.XXXXXX")"
    chmod 755 "$work" # apt's _apt sandbox user must be able to write downloads here
  fi
  mkdir -p "$work/$pkg"
  chmod 777 "$work/$pkg"
  echo "fetch-data: downloading $pkg"
  if ! (cd "$work/$pkg" && apt-get download "$pkg" >/dev/null 2>"$work/$pkg.err"); then
    if [ "$updated" -eq 0 ] && [ "$(id -u)" -eq 0 ]; then
      echo "fetch-data: $pkg not downloadable yet; running apt-get update"
      apt-get update >/dev/null || echo "fetch-data: apt-get update failed (offline?)" >&2
      updated=1
    elif [ "$updated" -eq 0 ] && command -v sudo >/dev/null 2>&1; then
      echo "fetch-data: $pkg not downloadable yet; running sudo apt-get update"
      sudo apt-get update >/dev/null || echo "fetch-data: apt-get update failed (offline?)" >&2
      updated=1
    fi
    if ! (cd "$work/$pkg" && apt-get download "$pkg" >/dev/null 2>"$work/$pkg.err"); then
      echo "fetch-data: ERROR: apt-get download $pkg failed:" >&2
      sed 's/^/  /' "$work/$pkg.err" >&2
      unavailable[$pkg]=1
      return 1
    fi
  fi
  local deb
  deb="$(ls "$work/$pkg"/*.deb | head -n 1)"
  dpkg -x "$deb" "$work/$pkg/root"
  extracted[$pkg]="$work/$pkg/root"
}

for entry in "${entries[@]}"; do
  IFS='|' read -r pkg inner name <<<"$entry"
  if [ -s "$dest/$name" ]; then
    echo "fetch-data: $name already present, skipped"
    continue
  fi
  if ! extract_package "$pkg"; then
    failed=1
    continue
  fi
  src="${extracted[$pkg]}/$inner"
  if [ ! -f "$src" ] && [ -f "$src.gz" ]; then # docs may be gzip-compressed by dh_compress
    gzip -dc "$src.gz" >"$dest/$name.part" && mv "$dest/$name.part" "$dest/$name"
  elif [ -f "$src" ]; then
    cp "$src" "$dest/$name.part" && mv "$dest/$name.part" "$dest/$name"
  else
    echo "fetch-data: ERROR: $inner is not in package $pkg" >&2
    failed=1
    continue
  fi
  echo "fetch-data: $name <- $pkg ($(stat -c %s "$dest/$name") bytes)"
done

if [ "$failed" -ne 0 ]; then
  echo "fetch-data: some volumes are missing (tests that need them will be skipped)" >&2
  exit 1
fi
echo "fetch-data: volumes in $dest"
