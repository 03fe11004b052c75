#!/bin/bash
# The share of a benchmark case's samples that named functions take, binaries alternated
# ROUNDS times. Where another tenant's load moves wall times by more than a change gains, the
# share of one pass in the same run moves far less: the load slows every pass alike. Prints a
# line per run: the binary, each PATTERN's share of the samples (%), and with two patterns or
# more the first share over the second. PATTERN is an awk regular expression on perf's symbol
# names; PERF_DELAY_MS=N leaves the first N ms (the case's set-up) out of the samples.
#   bench/perf_shares.sh FILTER ROUNDS 'PATTERN[,PATTERN...]' BINARY...
#   bench/perf_shares.sh 'BM_SphForces/n:30/order:2/threads:1' 2 '::forces$,::kinematics$' \
#       /tmp/fesph_bench_before build/fesph_bench
set -euo pipefail
if [ $# -lt 4 ]; then
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
filter=$1 rounds=$2 patterns=$3
shift 3
command -v perf >/dev/null || { echo "perf_shares.sh: perf is not installed (linux-perf)" >&2; exit 2; }
for binary in "$@"; do
  [ -x "$binary" ] || { echo "perf_shares.sh: $binary is not an executable" >&2; exit 2; }
done
data=$(mktemp)
trap 'rm -f "$data" "$data.old"' EXIT
delay=()
[ -n "${PERF_DELAY_MS:-}" ] && delay=(-D "$PERF_DELAY_MS")
for ((round = 1; round <= rounds; ++round)); do
  for binary in "$@"; do
    perf record -q -e cpu-clock "${delay[@]}" -o "$data" "$binary" --benchmark_filter="$filter" \
      >/dev/null 2>&1 || { echo "perf_shares.sh: $binary failed under perf" >&2; exit 1; }
    perf report -i "$data" --no-children --sort sym --stdio 2>/dev/null |
      awk -v binary="$binary" -v patterns="$patterns" '
        BEGIN { n = split(patterns, p, ",") }
        /^#/ || NF < 3 { next }
        {
          share = $1; sub(/%/, "", share)
          name = $0; sub(/^[^]]*\] /, "", name)
          for (k = 1; k <= n; ++k) if (name ~ p[k]) s[k] += share
        }
        END {
          line = binary
          for (k = 1; k <= n; ++k) line = line sprintf("  %s %.2f%%", p[k], s[k])
          if (n >= 2 && s[2] > 0) line = line sprintf("  ratio %.3f", s[1] / s[2])
          print line
        }'
  done
done
