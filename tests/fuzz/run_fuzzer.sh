#!/bin/sh
# Runs one libFuzzer target for $AERIAL_FUZZ_SECONDS (default 20) from its seed corpus, with
# libFuzzer's random seed $AERIAL_FUZZ_SEED (default 0: a new one each run; CI fixes it, so that a
# green commit stays green), and prints
# one line "fuzz NAME: RUNS runs in SECONDS s, ..." (libFuzzer's own figures), also written to
# WORK_DIR/summary.txt.
# New inputs go into WORK_DIR/corpus, crashing inputs into WORK_DIR/ as crash-*, timeout-*, ...
# Usage: run_fuzzer.sh FUZZER SEED_DIR WORK_DIR
set -eu
fuzzer=$1 seeds=$2 work=$3
seconds=${AERIAL_FUZZ_SECONDS:-20}
name=$(basename "$fuzzer")
mkdir -p "$work/corpus"
log="$work/fuzz.log"
status=0
"$fuzzer" -max_total_time="$seconds" -seed="${AERIAL_FUZZ_SEED:-0}" -timeout=60 -rss_limit_mb=2560 -max_len=4096 \
    -print_final_stats=1 -artifact_prefix="$work/" "$work/corpus" "$seeds" >"$log" 2>&1 ||
    status=$?
runs=$(sed -n 's/^Done \([0-9]*\) runs in \([0-9]*\) second.*/\1 runs in \2 s/p' "$log" | tail -n 1)
if [ "$status" -ne 0 ] || [ -z "$runs" ]; then
    tail -n 60 "$log"
    echo "fuzz $name: FAILED (exit $status); the input is in $work/, the log in $log" >&2
    exit 1
fi
echo "fuzz $name: $runs, $(find "$work/corpus" -type f | wc -l) inputs found in $work/corpus" |
    tee "$work/summary.txt"
