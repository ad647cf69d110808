#!/usr/bin/env bash
# The farm's failover, timed (docs/farm.md, "A bad node is left behind"):
# the built-in film's scene as a 4-shard chain on the two-node Slurm of
# scripts/slurm_up.sh, once with both nodes healthy and once with node1
# broken (its lmfilm a wrapper that exits 1), each from submission until
# no job of the chain is queued; prints both wall times, the failures
# and the later jobs. Both nodes share this machine's cores, so the
# ratio shows the cost of the failed attempts and the resubmissions,
# not of losing a node's cores.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
bin=$PWD/target/release/lmfilm
scene=$PWD/scenes/tennis/showcase.lm
root=$(mktemp -d /tmp/lmfilm-bench-farm.XXXXXX)
cat >"$root/broken-lmfilm" <<WRAP
#!/bin/bash
if [ "\${SLURMD_NODENAME:-}" = node1 ]; then echo "lmfilm: cannot run on this node" >&2; exit 1; fi
exec '$bin' "\$@"
WRAP
chmod +x "$root/broken-lmfilm"
chain() { # chain NAME LMFILM: seconds from submission to the chain's end
  local dir="$root/$1" start ids
  start=$(date +%s.%N)
  "$bin" farm slurm "$scene" -o "$dir" --shards 4 --cpus 1 --width 480 --height 270 --spp 3 \
    --lmfilm "$2" >/dev/null
  while :; do
    ids=$(awk '{print $2}' "$dir/farm/jobs.txt"; ls "$dir/farm/retries" 2>/dev/null | sed 's/.*@//')
    if ! squeue -h -o %F | grep -qxF -f <(echo "$ids"); then break; fi
    sleep 0.5
  done
  echo "$(date +%s.%N) - $start" | bc
  "$bin" verify "$dir" >/dev/null
}
healthy=$(chain healthy "$bin")
broken=$(chain broken "$root/broken-lmfilm")
echo "healthy chain: ${healthy} s"
echo "one node broken: ${broken} s ($(ls "$root/broken/farm/failed" | wc -l) failed attempts, $(ls "$root/broken/farm/retries" | wc -l) later jobs)"
cmp "$root/healthy/frames/showcase.0100.png" "$root/broken/frames/showcase.0100.png" && echo "frames identical"
"$bin" farm status "$root/broken" | sed -n '/nodes that failed/,$p'
rm -rf "$root"
