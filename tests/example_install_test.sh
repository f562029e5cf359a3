#!/usr/bin/env bash
# The core as a CMake package (issue 9): installs the build tree into a fresh prefix, builds
# examples/ against it with find_package(granular), and runs the example.
# Usage: example_install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build=$1 source=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
step() {  # quiet unless it fails
  local log="$work/$1.log"
  shift
  if ! "$@" > "$log" 2>&1; then
    cat "$log"
    echo "FAILED: $*"
    exit 1
  fi
}
step install cmake --install "$build" --prefix "$work/prefix"
test -f "$work/prefix/lib/cmake/granular/granularConfig.cmake" || {
  echo "FAILED: no granularConfig.cmake installed"
  exit 1
}
step configure cmake -S "$source/examples" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  "-DCMAKE_PREFIX_PATH=$work/prefix"
step build cmake --build "$work/build" -j2
"$work/build/custom_scene"
