#!/usr/bin/env bash
# Runs one harness for a while, politely: one process, lowest priority, bounded memory and time.
#   tests/fuzz/run.sh <map|bsp|textures|q3_shader|archive|models> <seconds> <work dir> [seed dir...]
# New corpus entries go to <work dir>/corpus, crashes/timeouts/OOMs to <work dir>/artifacts/.
# Expects the harnesses in build-fuzz/ (see README.md here). Extra libFuzzer flags: FUZZ_FLAGS.
set -euo pipefail
name=$1 seconds=$2 work=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
case $name in
  map) maxlen=32768 ;;
  bsp) maxlen=65536 ;;
  *) maxlen=16384 ;;
esac
mkdir -p "$work/corpus" "$work/artifacts"
exec nice -n 19 "$root/build-fuzz/tests/fuzz/fuzz_$name" \
  -dict="$here/$name.dict" -max_len=$maxlen -rss_limit_mb=2048 -timeout=10 \
  -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
  ${FUZZ_FLAGS:-} "$work/corpus" "$@"
