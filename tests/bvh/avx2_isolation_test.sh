#!/usr/bin/env bash
# The AVX2 compilation of the SAH builder (bvh/binned_sah_avx2.cpp) must hold no AVX code outside
# bt::avx2: a function it shares with the baseline's compilation (a standard library template)
# may be the copy the linker keeps for both, and would then run on CPUs without AVX2.
# Usage: avx2_isolation_test.sh OBJECT... (bt_bvh's objects; the AVX2 one is picked by name)
set -euo pipefail
object=""
for o in "$@"; do [[ "$o" == *binned_sah_avx2.cpp.o ]] && object="$o"; done
[[ -n "$object" ]] || { echo "no binned_sah_avx2.cpp object among: $*" >&2; exit 1; }
# VEX-encoded instructions (v...) or ymm registers, by function, outside bt::avx2.
leaks=$(objdump -d -C --no-show-raw-insn "$object" |
  awk '/^[0-9a-f]+ <.*>:$/ { fn = $0; next } /\tv[a-z0-9]+ |%ymm/ { if (fn !~ /bt::avx2::/) print fn }' | sort -u)
if [[ -n "$leaks" ]]; then
  echo "AVX code outside bt::avx2 in $object:" >&2
  echo "$leaks" >&2
  exit 1
fi
echo "$object: all AVX code is in bt::avx2"
