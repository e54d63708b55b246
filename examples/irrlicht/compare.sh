#!/bin/sh
# Renders the Irrlicht example's RUNs (arb-FIDELITY, cpu or cpu-vbo) under Xvfb and aerial::scene's cpu and
# arb frames of the same scene, compares every RUN with both references and every pair of RUNs
# with aerial-compare, and fails when any max_lsb exceeds 3.
# usage: compare.sh EXAMPLE REFERENCE COMPARE XVFB_RUN OUT_DIR RUN...
set -eu
example=$1 reference=$2 compare=$3 xvfb=$4 out=$5
shift 5
dir="$out/$(echo "$*" | tr ' ' '+')"
mkdir -p "$dir"
for backend in cpu arb; do
    "$reference" --backend "$backend" --out "$dir/reference-$backend.png"
done
for run in "$@"; do
    case $run in
        cpu) flags="--path cpu" ;;
        cpu-vbo) flags="--path cpu --buffers vbo" ;;
        arb-*) flags="--path arb --fidelity ${run#arb-}" ;;
        *) echo "compare.sh: RUN: expected cpu, cpu-vbo or arb-FIDELITY, got '$run'" >&2; exit 2 ;;
    esac
    # shellcheck disable=SC2086
    "$xvfb" -a -s '-screen 0 1024x768x24' "$example" $flags --out "$dir/irrlicht-$run.png"
done
worst=0
check() {  # NAME_A NAME_B
    line=$("$compare" "$dir/$1.png" "$dir/$2.png" --diff "$dir/diff-$1-$2.png")
    echo "$1 vs $2: $line"
    max=$(echo "$line" | sed -n 's/.*max_lsb=\([0-9]*\).*/\1/p')
    test -n "$max" || { echo "no max_lsb in the aerial-compare output" >&2; exit 1; }
    if [ "$max" -gt "$worst" ]; then worst=$max; fi
}
previous=""
for run in "$@"; do
    check "irrlicht-$run" reference-cpu
    check "irrlicht-$run" reference-arb
    for other in $previous; do check "irrlicht-$other" "irrlicht-$run"; done
    previous="$previous $run"
done
check reference-cpu reference-arb
test "$worst" -le 3 || { echo "max_lsb=$worst > 3 (diffs in $dir)" >&2; exit 1; }
