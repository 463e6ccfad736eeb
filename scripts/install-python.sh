#!/usr/bin/env bash
# Makes `import candela` work: writes candela.pth, naming this build's package folder
# (build/python), into the site-packages of each Python 3 interpreter given (default: `python3`
# on PATH and Debian's /usr/bin/python3). With a virtual environment active, `python3` is the
# venv's: run this once inside the venv to use Candela there (it needs NumPy in the venv:
# `python3 -m venv --system-site-packages` lends it Debian's python3-numpy).
#   scripts/install-python.sh [PYTHON...]
# As root the .pth goes to the interpreter's own site-packages (for Debian's python3:
# /usr/local/lib/python3.11/dist-packages); otherwise to the user's (~/.local/lib/...), which a
# venv does not read: there, run it with the venv active.
set -euo pipefail
cd "$(dirname "$0")/.."
package_dir="$(pwd)/build/python"
[ -f "$package_dir/candela/__init__.py" ] || { echo "install-python: $package_dir/candela is missing (build first: scripts/setup.sh)" >&2; exit 2; }
interpreters=("$@")
if [ ${#interpreters[@]} -eq 0 ]; then
    interpreters=()
    command -v python3 >/dev/null 2>&1 && interpreters+=("$(command -v python3)")
    [ -x /usr/bin/python3 ] && interpreters+=(/usr/bin/python3)
fi
declare -A done_sites=()
for python in "${interpreters[@]}"; do
    # The interpreter's own site-packages when it is writable (root, or a venv), else the user's.
    site=$("$python" - <<'PY'
import os, site, sys, sysconfig
candidates = [sysconfig.get_paths()["purelib"]]
if sys.prefix == sys.base_prefix:  # not a venv: the user site is read too
    candidates.append(site.getusersitepackages())
for path in candidates:
    parent = path
    while not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if os.access(parent, os.W_OK):
        print(path)
        break
PY
)
    if [ -z "$site" ]; then
        echo "install-python: no writable site-packages for $python; use PYTHONPATH=$package_dir" >&2
        continue
    fi
    [ -n "${done_sites[$site]:-}" ] && continue
    done_sites[$site]=1
    mkdir -p "$site"
    printf '%s\n' "$package_dir" > "$site/candela.pth.tmp" && mv "$site/candela.pth.tmp" "$site/candela.pth"
    echo "install-python: $python imports candela from $package_dir (through $site/candela.pth)"
done
