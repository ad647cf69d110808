#!/bin/sh
# The film pipeline's throughput (issue 45), measured in one run on this
# machine: the built-in film (Whitted, 3 spp) with 1 and with 2 threads,
# its serial fraction s = 2·T2/T1 − 1 and CPU busy at 2 threads, the
# stage breakdown, and the render stage of a 1920×1080 frame per sample
# against the forest still's (whole still: load, build, render, PNG).
# Run from the repository root: `make bench-film` (about 4 minutes on 2
# cores). THREADS_HIGH=16 times 16 threads against 2 instead.
set -e
HIGH=${THREADS_HIGH:-2}
cargo build --release --quiet
BIN=./target/release/lmfilm
OUT=target/bench-film
rm -rf "$OUT"
mkdir -p "$OUT"
[ -f target/forest.obj ] || python3 ../shared/anchors/make_forest_obj.py 16 11 target/forest.obj

# wall and CPU seconds of a command: "wall cpu"
timed() {
    /usr/bin/time -f "%e %U %S" -o "$OUT/time" "$@" > /dev/null 2> "$OUT/err" || { cat "$OUT/err"; exit 1; }
    awk '{ printf "%s %.2f", $1, $2 + $3 }' "$OUT/time"
}

echo "== the built-in film, 351 frames, 480x270, 3 spp (run, a fresh folder each)"
# --threads sizes the renderer's pool and the derivation's and the
# writer's beside it (RAYON_NUM_THREADS any other); each run is held to
# as many processors as it has threads (the pipeline's stages share
# them), so that T1 is the whole work done on one core.
PIN1="taskset -c 0"
PINN="taskset -c 0-$((HIGH - 1))"
command -v taskset > /dev/null || { PIN1=""; PINN=""; }
set -- $(timed env RAYON_NUM_THREADS=1 $PIN1 $BIN run -o "$OUT/t1" --threads 1)
T1=$1
echo "1 thread:  $1 s wall, $2 s CPU"
set -- $(timed env RAYON_NUM_THREADS=$HIGH $PINN $BIN run -o "$OUT/tn" --threads "$HIGH" --timings)
TN=$1
CPU=$2
echo "$HIGH threads: $1 s wall, $2 s CPU"
grep -A20 '^timings' "$OUT/err" || true
echo "$T1 $TN $CPU $HIGH" | awk '{
    s = ($4 * $2 / $1 - 1) / ($4 - 1);
    printf "serial fraction s = %.3f (from T1 = %s s, T%d = %s s)\n", s, $1, $4, $2;
    printf "CPU busy at %d threads: %.0f %%\n", $4, 100 * $3 / $2;
    printf "speed-up: %.2fx\n", $1 / $2 }'
cmp -s "$OUT/t1/frames/lmfilm.0200.png" "$OUT/tn/frames/lmfilm.0200.png" && echo "frame 200: same bytes at 1 and $HIGH threads"

echo "== per sample: a 1920x1080 film frame (render stage) against the forest still"
$BIN still scenes/tennis/showcase.lm scenes/tennis/match.lm scenes/tennis/landscape.lm --frame 150 --width 1920 --height 1080 --spp 3 --timings -o "$OUT/film1080.png" > /dev/null 2> "$OUT/err1080"
FRAME=$(awk '/^  render /{ print $2 }' "$OUT/err1080")
WALL1080=$(awk '/^  acceleration build /{ a = $3 } /^  encode PNG /{ p = $3 } END { print a + p }' "$OUT/err1080")
set -- $(timed $BIN still scenes/bench/forest.lm --width 1920 --height 1080 --spp 16 -o "$OUT/forest.png")
FOREST=$1
echo "$FRAME $WALL1080 $FOREST" | awk '{
    film = $1 / (1920 * 1080 * 3); forest = $3 / (1920 * 1080 * 16);
    printf "film frame render stage %.3f s (+ %.3f s BVH build and PNG) for 6.2 M samples: %.1f ns/sample\n", $1, $2, film * 1e9;
    printf "forest still %.3f s for 33.2 M samples: %.1f ns/sample\n", $3, forest * 1e9;
    printf "per-sample ratio film/forest: %.2f\n", film / forest }'
