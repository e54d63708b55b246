#!/bin/sh
# The sample's headless flythrough against its golden frames (tests/scene/golden/): of 11 frames
# without the readout, noon (0), fog (5, the sun 8 deg up), the end of civil twilight (7, the sun
# 6.4 deg down) and the night (10, the sun 15 deg down, the first quarter moon and the stars), at
# a loose tolerance, since they cover a whole pipeline (terrain, sky cubemap, sun sprite, stars and
# moon, the update policy) and a Mesa update may move edges by a pixel.
#
#   check_sample_goldens.sh SAMPLE COMPARE GOLDEN_DIR OUT_DIR [--record]
#
# Tolerance per frame (aerial-compare's bounds, TOLERANCE below): p99_lsb <= 4 and at most 1 % of
# the pixels off by more than 2 steps. --record re-renders the goldens and writes RENDERER.txt
# instead of comparing.
set -eu
sample=$1 compare=$2 golden=$3 out=$4 record=${5:-}
export LP_NUM_THREADS=1 GALLIUM_DRIVER=llvmpipe
TOLERANCE="--p99-lsb 4 --max-over2 0.01"
line=$("$sample" --headless --frames 11 --size 240x135 --no-readout --gl osmesa --out "$out")
echo "$line"
if [ "$record" = --record ]; then
    for i in 0000 0005 0007 0010; do cp "$out/frame_$i.png" "$golden/frame_$i.png"; done
    renderer=${line#*renderer=\"}
    renderer=${renderer%%\"*}
    {
        echo "Golden frames of aerial-sample, made by: tests/scene/check_sample_goldens.sh ... --record"
        echo "Command: aerial-sample --headless --frames 11 --size 240x135 --no-readout --gl osmesa"
        echo "GL_RENDERER: $renderer"
        echo "Environment: LP_NUM_THREADS=1 GALLIUM_DRIVER=llvmpipe"
    } >"$golden/RENDERER.txt"
    echo "recorded $golden"
    exit 0
fi
status=0
for i in 0000 0005 0007 0010; do
    # shellcheck disable=SC2086
    if result=$("$compare" "$golden/frame_$i.png" "$out/frame_$i.png" --diff "$out/diff_$i.png" \
        $TOLERANCE); then
        echo "frame_$i: $result"
    else
        echo "frame_$i: $result"
        echo "frame_$i differs from the golden beyond $TOLERANCE (diff: $out/diff_$i.png)"
        status=1
    fi
done
exit $status
