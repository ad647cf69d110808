#!/bin/sh
# The path tracer against Mitsuba 3's `path` integrator on the peers'
# forest under a uniform sky (0.5) and a sun (irradiance pi, a thesis
# light of colour 1), grey diffuse albedo 0.5, 4 bounces (Mitsuba's
# max_depth 5 counts the camera ray and the light's segment: lmfilm's
# --max-depth 3), one right after the other on this machine:
#  1. agreement: both at 1024 spp against a 4096-spp Mitsuba reference,
#     per-pixel mean difference and RMSE, and the noise floor; on the
#     forest, then on the gallery exported as a mesh;
#  2. speed at equal samples: whole frame (load + build + render) at
#     640x480, 16 spp, against llvm_ad_rgb;
#  3. speed at equal error: time and RMSE against the reference at 16
#     and 64 spp (RMSE falls as 1/sqrt(spp): the time each needs for
#     the same error follows).
# Run from the repository root: `make bench-path`. Needs ../shared/anchors.
set -e
ANCHORS=${ANCHORS:-../shared/anchors}
ENV=target/anchors-env
[ -x "$ENV/bin/python" ] || sh "$ANCHORS/setup.sh" "$ENV"
[ -f target/forest.obj ] || python3 "$ANCHORS/make_forest_obj.py" 16 11 target/forest.obj
# The same triangles with a grey material lmfilm reads (Mitsuba's
# loader skips `mtllib` and `usemtl`).
if [ ! -f target/forest_grey.obj ] || [ target/forest.obj -nt target/forest_grey.obj ]; then
    { printf 'mtllib forest_grey.mtl\nusemtl grey\n'; cat target/forest.obj; } > target/forest_grey.obj
fi
printf 'newmtl grey\nKd 0.5 0.5 0.5\nKs 0 0 0\n' > target/forest_grey.mtl
cargo build --release --quiet
# The gallery's shapes and ground as a mesh, grey the same way.
./target/release/lmfilm export scenes/examples/gallery.lm -o target/gallery.obj > /dev/null
grep -v '^usemtl\|^mtllib' target/gallery.obj | { printf 'mtllib forest_grey.mtl\nusemtl grey\n'; cat; } > target/gallery_grey.obj
LM=./target/release/lmfilm
MI="$ENV/bin/python $ANCHORS/mitsuba_path.py target/forest.obj"
SUN="--sun 3.14159 --sky 0.5 --albedo 0.5 --depth 5"
OUT=target/bench_path
mkdir -p $OUT
W=${W:-160}
H=$((W * 3 / 4))
secs() { start=$(date +%s.%N); "$@" > /dev/null; end=$(date +%s.%N); echo "$end - $start" | bc; }
lm() { $LM still scenes/bench/forest_path.lm --integrator path --max-depth 3 --width "$1" --spp "$2" --frame "${4:-0}" -o "$3"; }

echo "== 1. agreement at ${W}x${H}: Mitsuba 4096 spp reference; both at 1024 spp"
$MI $W $H 4096 llvm_ad_rgb $OUT/mi_4096.exr $SUN
$MI $W $H 1024 llvm_ad_rgb $OUT/mi_1024.exr $SUN
lm $W 1024 $OUT/lm_1024.exr
lm $W 1024 $OUT/lm_1024_b.exr 1
"$ENV/bin/python" scripts/compare_exr.py $OUT/mi_4096.exr $OUT/mi_1024.exr $OUT/lm_1024.exr $OUT/lm_1024_b.exr
echo "lmfilm against Mitsuba, both 1024 spp (the pair's noise floor is the root of the sum of their squared RMSEs above):"
"$ENV/bin/python" scripts/compare_exr.py $OUT/mi_1024.exr $OUT/lm_1024.exr

echo "== 1b. agreement on the gallery (exported as a mesh) at ${W}x${H}: Mitsuba 4096 spp reference; both at 1024 spp"
MIG="$ENV/bin/python $ANCHORS/mitsuba_path.py target/gallery.obj"
$MIG $W $H 4096 llvm_ad_rgb $OUT/gmi_4096.exr $SUN
$MIG $W $H 1024 llvm_ad_rgb $OUT/gmi_1024.exr $SUN
for f in 0 1; do
    $LM still scenes/bench/gallery_path.lm --integrator path --max-depth 3 --width $W --spp 1024 --frame $f -o $OUT/glm_1024_$f.exr
done
"$ENV/bin/python" scripts/compare_exr.py $OUT/gmi_4096.exr $OUT/gmi_1024.exr $OUT/glm_1024_0.exr $OUT/glm_1024_1.exr
"$ENV/bin/python" scripts/compare_exr.py $OUT/gmi_1024.exr $OUT/glm_1024_0.exr

echo "== 2. whole frame, 640x480, 16 spp, 4 bounces, all cores"
echo "lmfilm whole_frame_s $(secs lm 640 16 $OUT/lm_640.exr)"
$MI 640 480 16 llvm_ad_rgb $OUT/mi_640.exr $SUN
$MI 640 480 16 scalar_rgb $OUT/mi_640_scalar.exr $SUN

echo "== 3. equal error at ${W}x${H} (RMSE against the 4096-spp reference)"
for spp in 16 64; do
    echo "lmfilm spp $spp whole_frame_s $(secs lm $W $spp $OUT/lm_$spp.exr)"
    $MI $W $H $spp llvm_ad_rgb $OUT/mi_$spp.exr $SUN
done
"$ENV/bin/python" scripts/compare_exr.py $OUT/mi_4096.exr $OUT/lm_16.exr $OUT/mi_16.exr $OUT/lm_64.exr $OUT/mi_64.exr
