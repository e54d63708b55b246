#!/bin/sh
# Grades aerial-tess's own meshes of one scene twice: as built (--export-meshes writes each as
# OBJ) and read back from those files as a researcher's (--mesh ... --no-builtin). Every row of
# the second run must equal the built-in row of the same mesh in every figure: an external mesh
# is graded exactly like a built-in one.
# Usage: check_tess_reimport.sh AERIAL_TESS SCENE WORK_DIR
set -eu
tess=$1 scene=$2 work=$3
rm -rf "$work"
"$tess" --quick --no-chart --scene "$scene" --out "$work/builtin" \
    --export-meshes "$work/meshes" > "$work.builtin.txt"
"$tess" --quick --no-chart --scene "$scene" --out "$work/external" \
    --mesh "$work/meshes/$scene" --method external --no-builtin > "$work.external.txt"
# scene,method,level,vertices,triangles,max_lsb,p99_lsb,rmse_lsb,over1,over2,pixels,...: the
# figures are fields 4-11; an external row's level is the file stem METHOD-LEVEL.
awk -F, 'NR == FNR { if (FNR > 1) built[$2 "-" $3] = $4 "," $5 "," $6 "," $7 "," $8 "," $9 "," $10 "," $11; next }
         FNR > 1 { rows++; got = $4 "," $5 "," $6 "," $7 "," $8 "," $9 "," $10 "," $11
                   if (!($3 in built)) { print "no built-in row for " $3; bad++ }
                   else if (built[$3] != got) { print $3 ": " got " against " built[$3]; bad++ } }
         END { if (rows == 0) { print "no external rows"; exit 1 }
               if (bad > 0) { printf "%d of %d external meshes graded otherwise\n", bad, rows; exit 1 }
               printf "%d external meshes graded as built\n", rows }' \
    "$work/builtin/tess.csv" "$work/external/tess.csv"
