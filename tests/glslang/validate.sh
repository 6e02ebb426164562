#!/usr/bin/env bash
# Validates every generated stage shader with glslang (the Khronos reference front end), so a
# shader that Mesa happens to accept but the GLSL spec does not is caught here too.
set -uo pipefail
root=$1
shopt -s nullglob globstar
files=("$root"/glsl/**/*.comp "$root"/glsl/**/*.vert "$root"/glsl/**/*.frag "$root"/glsl/**/*.geom)
if [ ${#files[@]} -eq 0 ]; then echo "no generated shaders under $root/glsl"; exit 1; fi
failed=0
for f in "${files[@]}"; do
  if ! out=$(glslangValidator "$f" 2>&1); then
    echo "INVALID: ${f#$root/}"; echo "$out" | sed 's/^/  /'; failed=$((failed+1))
  fi
done
echo "glslang: ${#files[@]} shaders, $failed invalid"
[ $failed -eq 0 ]
