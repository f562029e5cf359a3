#!/usr/bin/env bash
# Installs the Debian 12 packages granular needs to build, test, benchmark and render (docs/architecture.md §2),
# and to run the sanitizer and fuzzing CI (scripts/ci-sanitizers.sh).
#
# Idempotent: asks dpkg-query which packages are missing and only then runs `apt-get update` once
# and one `apt-get install` of the missing ones; with everything present it changes nothing.
# Runs as root directly, or through sudo when not root.
#
# Usage: scripts/install-deps.sh [--dry-run]
#   --dry-run  only print the missing packages and the commands that would run
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake pkg-config
  # core, scene files, command line
  libeigen3-dev libtomlplusplus-dev libcli11-dev
  # tests, benchmarks, formatting
  libgtest-dev libbenchmark-dev clang-format
  # renderer: headless GL, PNG, text
  libosmesa6-dev libpng-dev libfreetype-dev fonts-dejavu-core
  # ParaView files (VTK's data model and XML writers; ~350 MB on a fresh machine)
  libvtk9-dev
  # runs split among processes (core/parallel): OpenMPI's library and mpirun
  libopenmpi-dev openmpi-bin
  # the Python module (python/, docs/python.md) and its tests, for Debian's /usr/bin/python3
  pybind11-dev python3-dev python3-numpy python3-pytest
  # granular-gui (optional window) and its test under a virtual X server
  libimgui-dev libglfw3-dev libstb-dev xvfb xauth
  # sanitizer and fuzzing builds (scripts/ci-sanitizers.sh): clang; its sanitizer and libFuzzer
  # runtimes (libclang-rt-14-dev, only recommended by clang, so not pulled in by
  # --no-install-recommends); LLVM's OpenMP runtime with the Archer tool for ThreadSanitizer
  clang libclang-rt-14-dev libomp-14-dev
)

dry_run=0
for arg in "$@"; do
  case "$arg" in
    --dry-run) dry_run=1 ;;
    -h | --help)
      sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "install-deps: unknown argument '$arg' (try --help)" >&2
      exit 2
      ;;
  esac
done

# A package counts as present only when dpkg says it is fully installed ("installed"); one that
# was removed but left its configuration ("config-files") or half-installed counts as missing.
missing=()
for pkg in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)"
  if [[ "$status" != "installed" ]]; then
    missing+=("$pkg")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages are installed; nothing to do."
  exit 0
fi

echo "install-deps: missing ${#missing[@]} of ${#packages[@]} packages: ${missing[*]}"

if [[ "$(id -u)" -eq 0 ]]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "install-deps: not root and sudo is not available; run as root:" >&2
  echo "  apt-get update && apt-get install -y --no-install-recommends ${missing[*]}" >&2
  exit 1
fi

run() {
  echo "+ $*"
  if [[ $dry_run -eq 0 ]]; then
    "$@"
  fi
}

run "${as_root[@]}" apt-get update
run "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y --no-install-recommends "${missing[@]}"

if [[ $dry_run -eq 0 ]]; then
  echo "install-deps: installed ${missing[*]}"
fi
