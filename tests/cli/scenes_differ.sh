#!/bin/sh
# tests/cli/scenes_differ.sh QUADCAST WORKDIR SCENE_A SCENE_B [RENDER FLAGS...] -- two scenes that
# differ in one documented key must render differently (a key that is parsed and then dropped
# gives identical pictures). Renders both with the GL renderer and with --cpu; prints
# "scenes-differ: FAILED ..." when a render fails or two pictures are byte-identical,
# "scenes-differ: done" at the end.
set -u
quadcast=$1 work=$2 a=$3 b=$4
shift 4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "scenes-differ: FAILED: $*"; }
for mode in gl cpu; do
    flag=
    [ $mode = cpu ] && flag=--cpu
    "$quadcast" render "$a" $flag "$@" -o "$work/a_$mode.png" || fail "$mode render of $a"
    "$quadcast" render "$b" $flag "$@" -o "$work/b_$mode.png" || fail "$mode render of $b"
    cmp -s "$work/a_$mode.png" "$work/b_$mode.png" && fail "$mode: $(basename "$a") and $(basename "$b") render identically"
done
echo "scenes-differ: done"
