#!/bin/sh
# The bytes of every output of every scene, as one sha256 a line, so that
# a change meant to keep behaviour (a refactor) can be checked to:
#
#     sh scripts/output_hashes.sh target/release/lmfilm > before.txt
#     ... change the code, build again ...
#     sh scripts/output_hashes.sh target/release/lmfilm > after.txt
#     diff before.txt after.txt            # empty: nothing changed
#
# For each scene (and the scene pairs of the physics films and the
# built-in film): `run` at the preview preset on a small image (the
# manifest, which hashes every frame, the soundtrack and the MP4 when
# ffmpeg is installed), `print` at the first and the middle frame in full,
# `trace`, `export` and `still` at the middle frame, and `sound` of the
# scene. A line is `scene command exit-code sha256-of-stdout+outputs`, so
# a command that fails, and how, is recorded too (its message included).
# The work happens in a fresh temporary folder, removed at the end.
set -u
LMFILM=$(cd "$(dirname "${1:?usage: output_hashes.sh PATH/TO/lmfilm}")" && pwd)/$(basename "$1")
cd "$(dirname "$0")/.."
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# Hash of a command's exit code, standard output and error, and the files
# it wrote under $WORK/out (names and bytes, in name order).
record() {
    label=$1
    shift
    rm -rf "$WORK/out" && mkdir -p "$WORK/out"
    "$LMFILM" "$@" >"$WORK/stdout" 2>"$WORK/stderr"
    code=$?
    # Paths of the temporary folder differ from run to run, and progress
    # lines (shown once a stage runs for 2 s) carry timings.
    sed "s|$WORK|WORK|g; /frames\/s · .* s left$/d" "$WORK/stdout" "$WORK/stderr" >"$WORK/text"
    files=$(cd "$WORK/out" && find . -type f | LC_ALL=C sort)
    sum=$( (cat "$WORK/text"; for f in $files; do echo "$f"; cat "$WORK/out/$f"; done) |
        sha256sum | cut -d' ' -f1)
    echo "$label $code $sum"
}

# The frame in the middle of a scene's film, from its trace.
middle() {
    n=$("$LMFILM" trace "$@" 2>/dev/null | wc -l)
    echo $((n / 2))
}

small="--preset preview --width 96 --height 54"
for scene in scenes/examples/*.lm scenes/physics/*.lm scenes/actors/*.lm scenes/bench/forest_instanced.lm; do
    mid=$(middle "$scene")
    record "$scene run" run "$scene" -o "$WORK/out/film" $small
    record "$scene print0" print "$scene" --format full
    record "$scene print$mid" print "$scene" --frame "$mid" --format full
    record "$scene trace" trace "$scene"
    record "$scene export$mid" export "$scene" --frame "$mid" -o "$WORK/out/x.obj"
    record "$scene still$mid" still "$scene" --frame "$mid" -o "$WORK/out/x.png" $small
    record "$scene sound" sound "$scene" -o "$WORK/out/s/soundtrack.wav"
done
for pair in "tree ball" "tree airplane"; do
    set -- $pair
    record "physics/$1+$2 run" run "scenes/physics/$1.lm" "scenes/physics/$2.lm" \
        -o "$WORK/out/film" $small
done
record "built-in run" run -o "$WORK/out/film" $small
