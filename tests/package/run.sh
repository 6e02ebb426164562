#!/usr/bin/env bash
# Installs quadcast into a temporary prefix, builds the consumers against it as a user would
# (the core alone; the README's example with the gl and image components), runs them, and
# checks the example's pictures (GL against the CPU reference). Also checks that the README
# shows the example's current text.
set -euo pipefail
src=$1; build=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
example="$src/examples/app/tensor_glyphs.cpp"
python3 - "$src/README.md" "$example" <<'PY'
import sys
readme, example = open(sys.argv[1]).read(), open(sys.argv[2]).read().rstrip("\n")
if "```cpp\n" + example + "\n```" not in readme:
    sys.exit("README.md does not show the current examples/app/tensor_glyphs.cpp")
print("README shows examples/app/tensor_glyphs.cpp (%d lines)" % (example.count("\n") + 1))
PY
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
test -x "$work/prefix/bin/quadcast" && test -x "$work/prefix/bin/quadcast-codegen" || { echo "quadcast and quadcast-codegen are not installed"; exit 1; }
for c in image scene volume slim gl; do  # each component alone
  cmake -S "$src/tests/package/component" -B "$work/component-$c" -DCMAKE_PREFIX_PATH="$work/prefix" -DQUADCAST_COMPONENT=$c \
    > "$work/component-$c.log" 2>&1 || { echo "find_package(quadcast COMPONENTS $c) failed:"; cat "$work/component-$c.log"; exit 1; }
done
echo "find_package(quadcast COMPONENTS c) finds each component alone: image scene volume slim gl"
cmake -S "$src/tests/package" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  -DQUADCAST_APP_SOURCE="$example" > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/consumer" -j 2 > "$work/build.log" || { cat "$work/build.log"; exit 1; }
"$work/consumer/consumer"
"$work/consumer/tensor_glyphs" 600 "$work/gl.png"
"$work/consumer/tensor_glyphs" 600 "$work/cpu.png" cpu
"$work/consumer/compare_png" "$work/gl.png" "$work/cpu.png"
