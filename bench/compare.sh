#!/bin/bash
# Compare benchmark binaries on a machine others share: runs them in turn, ROUNDS times, each
# with 3 repetitions of the cases FILTER selects, and prints per case and binary the minimum
# and the median of ns per item (s_per_item) over all repetitions. Alternating the binaries
# spreads another tenant's load over both; the minimum is the least disturbed run.
#   bench/compare.sh FILTER ROUNDS BINARY...
#   bench/compare.sh 'BM_ElementKernel/n:20/threads:1' 3 /tmp/fesph_bench_before build/fesph_bench
set -euo pipefail
if [ $# -lt 3 ]; then
  sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
filter=$1 rounds=$2
shift 2
for binary in "$@"; do
  [ -x "$binary" ] || { echo "compare.sh: $binary is not an executable" >&2; exit 2; }
done
results=$(mktemp)
trap 'rm -f "$results"' EXIT
for ((round = 1; round <= rounds; ++round)); do
  for binary in "$@"; do
    "$binary" --benchmark_filter="$filter" --benchmark_repetitions=3 --benchmark_format=json \
        2>/dev/null |
      python3 -c '
import json, sys
text = sys.stdin.read()
for case in (json.loads(text)["benchmarks"] if text.strip() else []):
    if case.get("run_type") == "iteration":
        print(sys.argv[1], case["name"], case["s_per_item"] * 1e9)
' "$binary" >> "$results"
  done
done
[ -s "$results" ] || { echo "compare.sh: no case matches '$filter'" >&2; exit 1; }
python3 - "$results" <<'EOF'
import collections, statistics, sys
ns = collections.defaultdict(list)
for line in open(sys.argv[1]):
    binary, case, value = line.split()
    ns[(case, binary)].append(float(value))
for (case, binary), v in sorted(ns.items()):
    print(f"{case}  {binary}  min {min(v):.1f}  median {statistics.median(v):.1f} ns  ({len(v)} runs)")
EOF
