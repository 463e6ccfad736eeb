#!/usr/bin/env bash
# Installs the Debian 12 packages Candela needs to build, test and benchmark.
# Only packages that are missing are installed; uses sudo when not root.
#   install-deps.sh         what building and testing need
#   install-deps.sh slurm   only Slurm and munge, for the render farm test (tests/farm/slurm_farm.sh)
#                           or a one-machine cluster; it starts no daemon
set -euo pipefail

packages=(
  cmake g++ make pkg-config
  libembree-dev libopenimageio-dev openimageio-tools libopenexr-dev libpng-dev libglm-dev
  catch2 libtbb-dev libpugixml-dev libcli11-dev zlib1g-dev libisal-dev
  libosmesa6-dev
  clang libclang-rt-14-dev llvm lld
  python3-dev pybind11-dev python3-numpy python3-pytest python3-nbclient python3-nbformat python3-ipykernel
  libcivetweb-dev libturbojpeg0-dev nlohmann-json3-dev chromium chromium-driver python3-selenium
  clang-format python3
)
# libisal-dev: ISA-L's inflate reads serialized meshes (faster than zlib's on the one stream).
# clang (Debian's clang 14) builds the sanitizer and fuzzing builds; libclang-rt-14-dev holds its
# run-times (ASan, UBSan, TSan and libFuzzer: libclang_rt.fuzzer-x86_64.a); llvm gives
# llvm-symbolizer, which turns sanitizer reports' addresses into file:line; lld links those
# builds (much faster than GNU ld on their large binaries). clang-format (Debian's 14) and python3
# run the cheap checks of scripts/test.sh's first stage (check-format.sh, gen-plugin-docs.py).
if [ "${1:-}" = slurm ]; then
  packages=(slurmctld slurmd slurm-client munge)
elif [ $# -gt 0 ]; then
  echo "usage: $0 [slurm]" >&2
  exit 2
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi

as_root=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
  else
    echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -q
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
