#!/usr/bin/env bash
# The sha256 of `lmfilm trace` over the first frames of every shipped
# scene, one line each: compare two builds for byte-identical behaviour
# (a restructuring must not change a byte).
#   scripts/trace_hashes.sh BIN [FRAMES] > hashes.txt
set -uo pipefail
bin=${1:?usage: trace_hashes.sh BIN [FRAMES]}
frames=${2:-0..40}
cd "$(dirname "$0")/.."
for f in $(ls scenes/*/*.lm | sort); do
  h=$("$bin" trace "$f" --frames "$frames" --allow-commands 2>&1 | sha256sum | cut -c1-16)
  echo "$h $f"
done
