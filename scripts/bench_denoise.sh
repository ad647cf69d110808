#!/bin/sh
# The denoiser (issue 57) against Intel Open Image Denoise on the same
# noisy frames and layers, and the denoised path look against Mitsuba 3's
# `path` in the same wall time. On the peers' forest (sky 0.5, sun pi,
# grey albedo 0.5, 4 bounces: scripts/bench_path.sh's scene) and on the
# gallery (scenes/examples/gallery.lm: its own materials, glass and a
# mirror), at W x 3W/4 (W=160 unless given):
#  1. a reference of REF_SPP samples (4096 unless given);
#  2. lmfilm at SPP samples (4 unless given), as rendered and denoised
#     (--denoise on), each timed as a whole `still`; OIDN (pyoidn, `RT`,
#     high quality, hdr) on the same noisy image with lmfilm's albedo and
#     normals; the RMSE of each against the reference;
#  3. (forest, when Mitsuba runs) Mitsuba `path` at the samples that take
#     the denoised frame's wall time, and its RMSE.
# Needs ../shared/anchors; OIDN in its own environment (ENV_OIDN, made
# here when missing: python3.11 with pyoidn, OpenEXR and numpy).
set -e
ANCHORS=${ANCHORS:-../shared/anchors}
ENV_OIDN=${ENV_OIDN:-$HOME/.cache/lmfilm-anchors/oidn-env}
[ -x "$ENV_OIDN/bin/python" ] || {
    python3.11 -m venv "$ENV_OIDN"
    "$ENV_OIDN/bin/pip" install -q pyoidn OpenEXR numpy
}
PY="$ENV_OIDN/bin/python"
W=${W:-160}
SPP=${SPP:-4}
REF_SPP=${REF_SPP:-4096}
OUT=target/bench_denoise
mkdir -p $OUT
cargo build --release --quiet
LM=./target/release/lmfilm
[ -f target/forest.obj ] || python3 "$ANCHORS/make_forest_obj.py" 16 11 target/forest.obj
if [ ! -f target/forest_grey.obj ] || [ target/forest.obj -nt target/forest_grey.obj ]; then
    { printf 'mtllib forest_grey.mtl\nusemtl grey\n'; cat target/forest.obj; } > target/forest_grey.obj
fi
printf 'newmtl grey\nKd 0.5 0.5 0.5\nKs 0 0 0\n' > target/forest_grey.mtl
secs() { start=$(date +%s.%N); "$@" > /dev/null 2>&1; end=$(date +%s.%N); echo "$end - $start" | bc; }

for scene in forest gallery; do
    case $scene in
        forest) file=scenes/bench/forest_path.lm; depth="--max-depth 3" ;;
        gallery) file=scenes/examples/gallery.lm; depth="" ;;
    esac
    still() { $LM still $file --integrator path $depth --width $W --spp "$1" -o "$2" ${3:+--denoise on}; }
    echo "== $scene at ${W}x$((W * 3 / 4)), $SPP spp against $REF_SPP"
    [ -f $OUT/${scene}_ref_$W.exr ] || still $REF_SPP $OUT/${scene}_ref_$W.exr > /dev/null
    t_noisy=$(secs still $SPP $OUT/${scene}_noisy.exr)
    t_ours=$(secs still $SPP $OUT/${scene}_ours.exr on)
    echo "lmfilm still: noisy $t_noisy s, denoised $t_ours s (whole process)"
    "$PY" "$ANCHORS/oidn_denoise.py" $OUT/${scene}_noisy.exr $OUT/${scene}_oidn.exr \
        --albedo $OUT/${scene}_ours.exr --normal $OUT/${scene}_ours.exr | tail -1
    "$PY" scripts/denoise_rmse.py $OUT/${scene}_ref_$W.exr \
        $OUT/${scene}_noisy.exr $OUT/${scene}_ours.exr $OUT/${scene}_oidn.exr
done

MI_ENV=target/anchors-env
if [ -x "$MI_ENV/bin/python" ]; then
    echo "== forest: Mitsuba path in the denoised frame's time"
    SUN="--sun 3.14159 --sky 0.5 --albedo 0.5 --depth 5"
    for spp in 4 8 16; do
        t=$(secs "$MI_ENV/bin/python" "$ANCHORS/mitsuba_path.py" target/forest.obj $W $((W * 3 / 4)) $spp llvm_ad_rgb $OUT/forest_mi_$spp.exr $SUN)
        echo "Mitsuba $spp spp: $t s (whole process)"
        "$PY" scripts/denoise_rmse.py $OUT/forest_ref_$W.exr $OUT/forest_mi_$spp.exr
    done
fi
