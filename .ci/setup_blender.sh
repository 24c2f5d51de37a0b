#!/usr/bin/env bash
# Blender for the tests (idempotent: skips what is already there).
#
#   .ci/setup_blender.sh dist/gridwalk-<version>-cp311-cp311-<platform>.whl
#
#   - Debian's `blender` (3.4.1, linked to the system Python 3.11), `Xvfb` and
#     `node` (to run the Flamenco job type's compiler script), with apt-get,
#     only when a command is missing;
#   - .venv-bpy45: `bpy` 4.5 LTS from PyPI;  .venv-bpy50: `bpy` 5.0.1 from PyPI;
#   - .venv-blender34: a venv of the system Python that Debian's blender embeds,
#     holding numpy and gridwalk for it (the tests pass its site-packages to
#     blender through PYTHONPATH);
#   - the given gridwalk wheel (+ numpy) in all three venvs.
# Measured on a 2-core machine: apt-get install ~30 s, each bpy venv ~20 s
# (a ~350 MB wheel), .venv-blender34 ~5 s.
set -euo pipefail
cd "$(dirname "$0")/.."
WHEEL=$(realpath "${1:?usage: .ci/setup_blender.sh path/to/gridwalk-*.whl}")
PY=${PYTHON:-python3}
SYSTEM_PY=/usr/bin/python3.11          # the interpreter Debian's blender links against
SUDO=""
[ "$(id -u)" = 0 ] || SUDO=sudo

step() { echo "setup_blender: $*"; }

if ! command -v blender >/dev/null || ! command -v Xvfb >/dev/null || ! command -v node >/dev/null \
    || ! "$SYSTEM_PY" -c "import ensurepip" 2>/dev/null; then
  step "apt-get install blender xvfb python3-venv nodejs"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq blender xvfb python3-venv nodejs >/dev/null
fi

# make_venv DIR PYTHON PIP_SPEC VERSION_GLOB: a venv whose `bpy` (or, with
# spec "-", nothing in particular) is installed once.
make_venv() {
  local dir=$1 python=$2 spec=$3 want=$4
  [ -x "$dir/bin/python" ] || "$python" -m venv "$dir"
  if [ "$spec" != "-" ]; then
    local have
    have=$("$dir/bin/python" -c "import importlib.metadata as m; print(m.version('bpy'))" 2>/dev/null || true)
    # shellcheck disable=SC2053
    if [[ "$have" != $want ]]; then
      step "$dir: pip install $spec"
      "$dir/bin/python" -m pip install -q "$spec"
    fi
  fi
  step "$dir: pip install gridwalk wheel"
  "$dir/bin/python" -m pip install -q numpy
  "$dir/bin/python" -m pip install -q --force-reinstall --no-deps "$WHEEL"
}

make_venv .venv-bpy45 "$PY" "bpy==4.5.*" "4.5.*"
make_venv .venv-bpy50 "$PY" "bpy==5.0.1" "5.0.1"
make_venv .venv-blender34 "$SYSTEM_PY" - -

# Smoke check: each Blender loads the cp311 extension.
for v in .venv-bpy45 .venv-bpy50; do
  "$v/bin/python" -c "import bpy, gridwalk, sys; print('setup_blender:', '$v', bpy.app.version_string, 'gridwalk', gridwalk.__version__); sys.stdout.flush(); from gridwalk.renderfarm.blender_exit import exit_now; exit_now(0)"
done
PYTHONPATH="$PWD/.venv-blender34/lib/python3.11/site-packages" blender -b --factory-startup -noaudio \
  --python-expr "import bpy, gridwalk; print('setup_blender: blender', bpy.app.version_string, 'gridwalk', gridwalk.__version__)" \
  2>&1 | grep "^setup_blender:"
