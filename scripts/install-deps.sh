#!/usr/bin/env bash
# Installs the Debian 12 packages simpli needs, only those that are missing (a re-run costs
# one dpkg query). Must run as root (or via sudo). See docs/building.md for what each is for.
set -euo pipefail

packages=(
  # toolchain
  g++ cmake make pkg-config
  # ParaView's VTK, its Python modules and the plugin SDK (one VTK: ParaView's; see
  # shared/reference/vtk_paraview_build.md), plus the -dev packages paraview-dev lacks
  paraview paraview-dev python3-paraview libopenmpi-dev libdouble-conversion-dev
  libglew-dev libx11-dev libgl-dev libpython3-dev
  # the plugin's GUI part (plugin/gui: ParaView's Qt client headers need Qt5 dev; OpenGL
  # because VTK::GUISupportQt links Qt5::OpenGL (without it CMake cannot generate); Svg and
  # Help only so that ParaView's CMake config finds every Qt component it asks for, without
  # configure warnings)
  qtbase5-dev libqt5opengl5-dev libqt5svg5-dev qttools5-dev
  # headless rendering for tests
  xvfb xauth
  # OpenCL (PoCL on the CPU), CLBlast and its tuners
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libclblast-dev clblast-utils
  # MPI (Open MPI, the one ParaView links): mpiexec -n K simpli train / infer (SIMPLI_USE_MPI)
  libopenmpi-dev openmpi-bin
  # libraries
  libopencv-dev libeigen3-dev nlohmann-json3-dev libcli11-dev libopenblas-dev
  # tests (PyTorch only for the test of scripts/convert_reference_checkpoint.py; NumPy for the
  # weight scripts' tests; tinygltf reads the GLB export back)
  libgtest-dev python3-torch python3-numpy libtinygltf-dev
)

bash "$(dirname "${BASH_SOURCE[0]}")/apt-install-missing.sh" install-deps "${packages[@]}"
