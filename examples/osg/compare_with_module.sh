#!/bin/sh
# Renders the example's frame with the OpenSceneGraph adapter and with the module's renderer,
# compares them with aerial-compare and fails when max_lsb exceeds 1.
# usage: compare_with_module.sh EXAMPLE COMPARE BACKEND MODEL OUT_DIR
set -eu
example=$1 compare=$2 backend=$3 model=$4 out=$5
mkdir -p "$out"
osg="$out/osg-$backend-$model.png" module="$out/module-$backend-$model.png"
"$example" --renderer osg --backend "$backend" --model "$model" --out "$osg"
"$example" --renderer module --backend "$backend" --model "$model" --out "$module"
line=$("$compare" "$osg" "$module" --diff "$out/diff-$backend-$model.png")
echo "$backend $model: $line"
max=$(echo "$line" | sed -n 's/.*max_lsb=\([0-9]*\).*/\1/p')
test -n "$max" || { echo "no max_lsb in the aerial-compare output" >&2; exit 1; }
test "$max" -le 1 || { echo "max_lsb=$max > 1 (diff: $out/diff-$backend-$model.png)" >&2; exit 1; }
