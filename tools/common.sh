# Shared by the README's two commands: install Debian packages, build, stage the add-on.
# Sourced, not run.
set -euo pipefail

MOLDTEX_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MOLDTEX_BUILD="${MOLDTEX_BUILD:-$MOLDTEX_ROOT/build}"
# The modern-Blender test targets: PyPI's bpy wheels (Blender as a Python module), the
# 4.2 LTS and 5.0 (the newest for CPython 3.11), each in its own venv.
MOLDTEX_BPY_VERSION="${MOLDTEX_BPY_VERSION:-4.2.23}"
MOLDTEX_BPY5_VERSION="${MOLDTEX_BPY5_VERSION:-5.0.1}"

# Installs the Debian packages named (as root; says what to run otherwise).
moldtex_apt_install() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    if [ "$(id -u)" != 0 ]; then
      echo "Missing Debian packages: ${missing[*]}; run this command as root (or with sudo)." >&2
      exit 1
    fi
    echo "== Installing Debian packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

moldtex_install_packages() {
  # OpenCL: Khronos headers to build the backend, the ICD loader, and PoCL (OpenCL on
  # the CPU) so the OpenCL path really runs here.
  moldtex_apt_install build-essential cmake pkg-config libgtest-dev libbenchmark-dev \
    libopenimageio-dev libembree-dev libeigen3-dev opencl-headers ocl-icd-opencl-dev pocl-opencl-icd \
    blender python3 python3-venv python3-pip \
    xvfb xauth  # a virtual X server for the interactive checks
}

moldtex_build() {
  echo "== Building into $MOLDTEX_BUILD"
  cmake -S "$MOLDTEX_ROOT" -B "$MOLDTEX_BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$MOLDTEX_BUILD" -j"$(nproc)"
}

# Python venv with a bpy wheel; prints the interpreter path.
#   moldtex_bpy_python                      -> build/venv-bpy, bpy $MOLDTEX_BPY_VERSION
#   moldtex_bpy_python venv-bpy5 5.0.1      -> build/venv-bpy5, bpy 5.0.1
moldtex_bpy_python() {
  local venv="$MOLDTEX_BUILD/${1:-venv-bpy}"
  local version="${2:-$MOLDTEX_BPY_VERSION}"
  if [ ! -x "$venv/bin/python" ]; then
    # bpy wheels are built for CPython 3.11: prefer an interpreter of that version.
    local py=python3
    command -v python3.11 >/dev/null && py=python3.11
    "$py" -m venv "$venv" >&2
  fi
  # (bpy.app.version_string is e.g. "4.2.23 LTS" or "5.0.1".)
  if ! "$venv/bin/python" -c "import bpy, sys; sys.exit(bpy.app.version_string.split()[0] != '$version')" >/dev/null 2>&1; then
    echo "== Installing bpy==$version from PyPI into $venv" >&2
    "$venv/bin/pip" install -q "bpy==$version" >&2
  fi
  echo "$venv/bin/python"
}
