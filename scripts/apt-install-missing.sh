#!/usr/bin/env bash
# Installs those of the given Debian packages that are missing (a re-run costs one dpkg query);
# shared by install-deps.sh and install-photos.sh. Needs root, or sudo.
#   bash scripts/apt-install-missing.sh LABEL PACKAGE...
# LABEL prefixes the messages ("install-deps: ...").
set -euo pipefail
label=$1
shift
missing=()
for p in "$@"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  echo "$label: all $# packages present"
  exit 0
fi
if [[ $(id -u) -ne 0 ]]; then
  if ! command -v sudo >/dev/null; then
    echo "$label: need root (or sudo) to install ${missing[*]}" >&2
    exit 1
  fi
  SUDO=sudo
else
  SUDO=
fi
echo "$label: installing ${#missing[@]} missing package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
