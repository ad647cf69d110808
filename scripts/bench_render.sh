#!/bin/sh
# Renders the peers' forest with lmfilm and with Embree / Mitsuba 3, one
# right after the other on this machine, and prints the figures side by
# side (docs/performance.md quotes their ratios). Run from the repository
# root: `make bench-render`. Needs ../shared/anchors (the anchor scripts).
set -e
ANCHORS=${ANCHORS:-../shared/anchors}
ENV=target/anchors-env
[ -x "$ENV/bin/python" ] || sh "$ANCHORS/setup.sh" "$ENV"
[ -f target/forest.obj ] || python3 "$ANCHORS/make_forest_obj.py" 16 11 target/forest.obj
cargo build --release --quiet
# An intrinsic left out of line (an AVX operation in a closure: closures do
# not inherit #[target_feature]) made AVX2 packets 4x slower once; refuse to
# time such a build.
if nm -C target/release/lmfilm | grep -q 'core_arch::x86.*::_mm'; then
    echo "target/release/lmfilm calls SIMD intrinsics out of line: see docs/performance.md" >&2
    exit 1
fi
# The casting rates come from one thread whatever the pool (the bench's
# loops); the criterion cases (actor vision, the render alone, against
# Mitsuba's render_s) use all cores, as Mitsuba does.
echo "== ray casting, one thread (primary + one shadow ray per hit), 640x480; then the render alone, all cores"
cargo bench --quiet --bench render
"$ENV/bin/python" "$ANCHORS/embree_rays.py" target/forest.obj 640 480
echo "== whole frame: load + build + render, 640x480, 16 spp, all cores"
start=$(date +%s.%N)
./target/release/lmfilm still scenes/bench/forest.lm --width 640 --height 480 --spp 16 -o target/lmfilm_forest.png
end=$(date +%s.%N)
echo "lmfilm whole_frame_s $(echo "$end - $start" | bc)"
# Issue 18's peer is the LLVM (JIT, packet) back-end; scalar_rgb for reference.
"$ENV/bin/python" "$ANCHORS/mitsuba_frame.py" target/forest.obj 640 480 16 llvm_ad_rgb target/mitsuba_forest_llvm.png
"$ENV/bin/python" "$ANCHORS/mitsuba_frame.py" target/forest.obj 640 480 16 scalar_rgb target/mitsuba_forest.png
