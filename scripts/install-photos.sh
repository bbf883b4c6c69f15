#!/usr/bin/env bash
# Installs the Debian packages whose photographs texture the synthetic training scenes
# (`"textures": "photo"` in a training config's "synthetic" section, `simpli make-scene
# --textures photo`): mate-backgrounds and plasma-workspace-wallpapers, only those that are
# missing (a re-run costs one dpkg query). Which files of them are used, with their authors and
# licences: docs/training_photos.md. Must run as root (or via sudo); needs apt's network access.
# Only training and make-scene read the photos; infer, render and eval never need them.
set -euo pipefail

packages=(mate-backgrounds plasma-workspace-wallpapers)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-photos: ${packages[*]} already installed"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  if ! command -v sudo >/dev/null; then
    echo "install-photos: need root (or sudo) to install ${missing[*]}" >&2
    exit 1
  fi
  SUDO=sudo
else
  SUDO=
fi
echo "install-photos: installing ${missing[*]} (about 140 MB download)"
export DEBIAN_FRONTEND=noninteractive
# A stale package list can name versions the mirror no longer has: try, then update and retry.
if ! $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"; then
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
echo "install-photos: done"
