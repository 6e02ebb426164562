#!/bin/sh
# tests/cli/output_checks.sh QUADCAST SCENE WORKDIR -- `quadcast render` output is whole or absent:
# prints "output-checks: FAILED ..." (the test's FAIL_REGULAR_EXPRESSION) for every case where
# an output is half written, left behind, replaced though it is no regular file, or where a
# render that should succeed fails; "output-checks: done" at the end.
set -u
quadcast=$1 scene=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
fail() { echo "output-checks: FAILED: $*"; }
render() { "$quadcast" render "$scene" --cpu --width 32 --height 24 "$@" 2>&1; }
leftovers() { ls -A | grep -q '^\.' && fail "$1: temporaries left: $(ls -A | tr '\n' ' ')"; }

# 1. The PNG and the PFM named alike: refused before rendering, nothing written.
render -o same.png --depth same.png && fail "identical -o and --depth exited 0"
[ -e same.png ] && fail "identical -o and --depth wrote same.png"
render -o ./same2.png --depth "$work/same2.png" && fail "identical -o and --depth (different spellings) exited 0"
[ -e same2.png ] && fail "identical -o and --depth (different spellings) wrote same2.png"

# 2. An existing output that is not a regular file is not replaced.
mkfifo fifo.png
render -o fifo.png && fail "-o FIFO exited 0"
[ -p fifo.png ] || fail "-o FIFO replaced the FIFO"
rm -f fifo.png

# 3. A directory that does not exist: the reason is given.
render -o no/such/dir/x.png | grep -q "No such file or directory" || fail "-o in a missing directory gave no reason"

# 4. A failed --depth write (file size limit: the PFM is larger than the PNG) leaves neither
#    file, and an old PNG stays untouched.
echo old > old.png
# (ulimit -f counts 512 bytes in dash, 1024 in bash: 8 blocks hold the PNG, not the 12 kB PFM)
( trap '' XFSZ; ulimit -f 8; "$quadcast" render "$scene" --cpu --width 64 --height 48 -o old.png --depth old.pfm 2>&1 ) &&
    fail "a failed PFM write exited 0"
[ "$(cat old.png)" = old ] || fail "a failed render replaced the old PNG"
[ -e old.pfm ] && fail "a failed PFM write left old.pfm"
leftovers "failed write"
rm -f old.png

# 5. Concurrent renders to one name: all succeed and the result is a whole PNG.
for i in 1 2 3 4 5 6; do (render -o shared.png --depth shared.pfm >/dev/null || echo "output-checks: FAILED: concurrent render $i failed") & done
wait
"$quadcast" render "$scene" --cpu --width 32 --height 24 -o check.png >/dev/null 2>&1
cmp -s shared.png check.png || fail "concurrent renders left a PNG that differs from a single render"
leftovers "concurrent renders"
rm -f shared.png shared.pfm check.png

# 6. SIGTERM while the outputs are being written removes the temporaries (and re-raises: status
#    143). The signal is sent when a temporary appears; a render that finished first proves nothing.
"$quadcast" render "$scene" --cpu --width 3000 --height 3000 -o sig.png --depth sig.pfm >/dev/null 2>&1 &
pid=$!
sent=
for i in $(seq 1 400); do
    if ls -A | grep -q '^\.sig'; then kill -TERM $pid 2>/dev/null && sent=yes; break; fi
    kill -0 $pid 2>/dev/null || break
    sleep 0.02
done
wait $pid
status=$?
if [ -n "$sent" ]; then
    leftovers "SIGTERM during the write"
    [ "$status" -eq 143 ] || [ -e sig.pfm ] || fail "SIGTERM during the write: status $status and no output"
else
    echo "output-checks: SIGTERM case inconclusive (the write was not seen)"
fi
echo "output-checks: done"
