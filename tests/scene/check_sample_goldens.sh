#!/bin/sh
# The sample's headless flythrough against its golden frames (tests/scene/golden/): of 11 frames
# without the readout, on the cpu backend noon (0), fog (5, the sun 8 deg up), the end of civil
# twilight (7, the sun 6.4 deg down, lit by the sun and the moon) and the night (10, the sun
# 15 deg down, the first quarter moon and the stars); on the arb backend the same twilight and
# night (its second, additive pass for the moon); at a loose tolerance, since they cover a whole
# pipeline (terrain, sky cubemap, sun sprite, stars and moon, the update policy) and a Mesa
# update may move edges by a pixel.
#
#   check_sample_goldens.sh SAMPLE COMPARE GOLDEN_DIR OUT_DIR [--record]
#
# Tolerance per frame (aerial-compare's bounds, TOLERANCE below): p99_lsb <= 4 and at most 1 % of
# the pixels off by more than 2 steps. --record re-renders the goldens and writes RENDERER.txt
# instead of comparing. Goldens are GOLDEN_DIR/BACKEND-frame_NNNN.png.
set -eu
sample=$1 compare=$2 golden=$3 out=$4 record=${5:-}
export LP_NUM_THREADS=1 GALLIUM_DRIVER=llvmpipe
TOLERANCE="--p99-lsb 4 --max-over2 0.01"
FLAGS="--headless --frames 11 --size 240x135 --no-readout --gl osmesa"
frames_of() { if [ "$1" = cpu ]; then echo 0000 0005 0007 0010; else echo 0007 0010; fi; }
status=0
for backend in cpu arb; do
    # shellcheck disable=SC2086
    line=$("$sample" $FLAGS --backend $backend --out "$out/$backend")
    echo "$line"
    for i in $(frames_of $backend); do
        name=$backend-frame_$i
        if [ "$record" = --record ]; then
            cp "$out/$backend/frame_$i.png" "$golden/$name.png"
            continue
        fi
        # shellcheck disable=SC2086
        if result=$("$compare" "$golden/$name.png" "$out/$backend/frame_$i.png" \
            --diff "$out/diff_$name.png" $TOLERANCE); then
            echo "$name: $result"
        else
            echo "$name: $result"
            echo "$name differs from the golden beyond $TOLERANCE (diff: $out/diff_$name.png)"
            status=1
        fi
    done
done
if [ "$record" = --record ]; then
    renderer=${line#*renderer=\"}
    renderer=${renderer%%\"*}
    {
        echo "Golden frames of aerial-sample, made by: tests/scene/check_sample_goldens.sh ... --record"
        echo "Command: aerial-sample $FLAGS --backend cpu|arb"
        echo "GL_RENDERER: $renderer"
        echo "Environment: LP_NUM_THREADS=1 GALLIUM_DRIVER=llvmpipe"
    } >"$golden/RENDERER.txt"
    echo "recorded $golden"
fi
exit $status
