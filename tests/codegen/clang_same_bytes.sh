#!/usr/bin/env bash
# generated/ must not depend on the compiler: build quadcast-codegen with Clang (the test suite
# itself is built with GCC) and check that it emits exactly the checked-in files.
set -euo pipefail
src=$1; work=$2
cxx=$(command -v clang++ || true)
if [ -z "$cxx" ]; then echo "clang++ is not installed (make deps installs it)"; exit 1; fi
cmake -S "$src" -B "$work" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_C_COMPILER="$(command -v clang)" \
  -DQUADCAST_BUILD_TESTS=OFF -DQUADCAST_BUILD_EXAMPLES=OFF -DQUADCAST_INSTALL=OFF -DCMAKE_BUILD_TYPE=Release > "$work.log" 2>&1 \
  || { cat "$work.log"; exit 1; }
cmake --build "$work" --target quadcast-codegen -j "$(nproc)" >> "$work.log" 2>&1 || { tail -50 "$work.log"; exit 1; }
"$work/codegen/quadcast-codegen" --check "$src/generated"
