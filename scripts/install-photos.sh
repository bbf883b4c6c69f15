#!/usr/bin/env bash
# Installs the Debian packages whose photographs texture the synthetic training scenes
# (`"textures": "photo"` in a training config's "synthetic" section, `simpli make-scene
# --textures photo`): mate-backgrounds and plasma-workspace-wallpapers, only those that are
# missing (a re-run costs one dpkg query). Which files of them are used, with their authors and
# licences: docs/training_photos.md. Must run as root (or via sudo); needs apt's network access.
# Only training and make-scene read the photos; infer, render and eval never need them.
set -euo pipefail

packages=(mate-backgrounds plasma-workspace-wallpapers)

# About 140 MB to download when missing.
bash "$(dirname "${BASH_SOURCE[0]}")/apt-install-missing.sh" install-photos "${packages[@]}"
