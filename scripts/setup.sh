#!/usr/bin/env bash
# One-command set-up on Debian 12: installs missing packages, builds Candela in Release (the
# program and the Python package), renders the example Cornell box to cbox.exr (and a PNG
# preview) in the repository root, and makes `python3 -c "import candela"` work
# (scripts/install-python.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
./build/candela render scenes/cbox.xml -o cbox.exr --png
echo "setup: rendered cbox.exr and cbox.png"
# `import candela` for python3 (docs/python.md).
./scripts/install-python.sh
