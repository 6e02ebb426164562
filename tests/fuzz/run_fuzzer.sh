#!/bin/sh
# tests/fuzz/run_fuzzer.sh FUZZER CORPUS SECONDS [WORK_CORPUS] -- runs one libFuzzer harness for
# SECONDS over the seed corpus (new inputs go to WORK_CORPUS, default a temporary directory, so
# the checked-in seeds stay small), inputs up to 64 kB, 2 GB of memory. Exit 77 (skipped) when
# the harness was not built (no Clang with libFuzzer, or `make fuzz-build` not run).
set -u
fuzzer=$1 corpus=$2 seconds=$3
[ -x "$fuzzer" ] || { echo "skipped: $fuzzer not built (needs clang with libFuzzer: make fuzz-build)"; exit 77; }
work=${4:-}
cleanup=
if [ -z "$work" ]; then
    work=$(mktemp -d)
    cleanup=$work
fi
mkdir -p "$work"
artifacts=${FUZZ_ARTIFACTS:-$(dirname "$fuzzer")/artifacts/$(basename "$fuzzer")}
mkdir -p "$artifacts"
log=$(mktemp)
"$fuzzer" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -timeout=20 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" "$work" "$corpus" >"$log" 2>&1
status=$?
grep -v 'NEW\|REDUCE\|pulse' "$log"
rm -f "$log"
[ -n "$cleanup" ] && rm -rf "$cleanup"
exit $status
