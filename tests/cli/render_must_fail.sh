#!/bin/sh
# tests/cli/render_must_fail.sh QUADCAST SCENE OUTPUT_PNG -- `quadcast render` on a bad scene:
# runs it (its messages go to this script's output, for the test's PASS_REGULAR_EXPRESSION),
# then prints "render-must-fail: FAILED ..." (the test's FAIL_REGULAR_EXPRESSION) when it
# exited 0, crashed, or left the output PNG behind.
set -u
quadcast=$1 scene=$2 out=$3
rm -f "$out"
"$quadcast" render "$scene" -o "$out" --width 32 --height 24 2>&1
status=$?
if [ "$status" -eq 0 ]; then
    echo "render-must-fail: FAILED: exit status 0 on a bad scene"
elif [ "$status" -gt 128 ]; then
    echo "render-must-fail: FAILED: killed by signal $((status - 128))"
else
    echo "render-must-fail: exit status $status"
fi
if [ -e "$out" ]; then
    echo "render-must-fail: FAILED: $out was written"
    rm -f "$out"
fi
exit 0
