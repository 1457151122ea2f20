#!/usr/bin/env bash
# The speed protocol of BENCHMARKS.md: `mcpose bench` run RUNS times one after the other (each
# run's JSON and text in out/bench/run_K.json and .txt), then per object the range and median
# over the runs of the median full iteration, of render + inlier and of each baseline's ratio,
# and how many runs meet the issue's targets (full iteration <= 3 ms, Embree >= 20x, OSMesa
# >= 30x). Machines are noisy: pause other work while it runs, and compare builds by
# alternating them, not by one run each.
# Usage: scripts/bench_runs.sh RUNS [mcpose bench options]
#        scripts/bench_runs.sh RUNS --summarize   (the summary of out/bench/run_1..RUNS again)
#   scripts/bench_runs.sh 6 --threads 2 --iterations 50 --repeats 15 --baselines embree,osmesa
#   scripts/bench_runs.sh 6 --threads 2 --iterations 50 --repeats 15 --baselines embree,osmesa --simd-target AVX2
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
RUNS=$1
shift
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
if [ "${1:-}" = "--summarize" ]; then
  for ((r = 1; r <= RUNS; r++)); do
    [ -e "out/bench/run_$r.txt" ] || { echo "bench_runs: out/bench/run_$r.txt is missing" >&2; exit 1; }
  done
else
  [ -x build/mcpose ] || { echo "bench_runs: build/mcpose is missing (run scripts/build.sh first)" >&2; exit 1; }
  mkdir -p out/bench
  for ((r = 1; r <= RUNS; r++)); do
    ./build/mcpose bench --dataset "$DATA/ycbv" --json "out/bench/run_$r.json" "$@" > "out/bench/run_$r.txt"
    echo "bench_runs: run $r of $RUNS done" >&2
  done
fi
head -2 out/bench/run_1.txt
# An object line: name tris lod culled frags | r+i (min- max) | full (min- max) hyp/s | baselines
# ("embree 136.5 ms 32.2x 0.01%  osmesa ...").
for ((r = 1; r <= RUNS; r++)); do
  awk -F'|' -v run="$r" 'NF >= 3 && $1 ~ /^[0-9][0-9][0-9]_/ {
      split($1, a, " "); split($2, ri, " "); split($3, fu, " ")
      printf "%s run %s ri %s full %s", a[1], run, ri[1], fu[1]
      n = split($4, b, " ")
      for (i = 1; i + 4 <= n; i += 5) { x = b[i + 3]; sub(/x$/, "", x); printf " %s %s", b[i], x }
      printf "\n" }' "out/bench/run_$r.txt"
done | sort -s -k1,1 | awk '
  function flush(   j, k, line) {
    if (name == "") return
    line = sprintf("%-22s full %s ms  r+i %s ms  <= 3 ms %d/%d", name, stat(fu, n, "%.2f"), stat(ri, n, "%.2f"), le3, n)
    for (j = 1; j <= nb; j++) {  # the baselines in the order the bench printed them
      k = names[j]
      line = line sprintf("  %s %sx, >= %d: %d/%d", k, stat_b(k), k == "embree" ? 20 : 30, bok[k], bn[k])
    }
    print line
    delete bv; delete bn; delete bok; delete names; nb = 0; n = 0; le3 = 0
  }
  # "min-max (median)" of v[1..m] in format f, v sorted in place.
  function stat(v, m, f,   i, j, t, med) {
    for (i = 2; i <= m; i++) for (j = i; j > 1 && v[j - 1] > v[j]; j--) { t = v[j]; v[j] = v[j - 1]; v[j - 1] = t }
    med = m % 2 ? v[(m + 1) / 2] : (v[m / 2] + v[m / 2 + 1]) / 2
    return sprintf(f "-" f " (" f ")", v[1], v[m], med)
  }
  function stat_b(k,   i, w) { for (i = 1; i <= bn[k]; i++) w[i] = bv[k, i]; return stat(w, bn[k], "%.1f") }
  $1 != name { flush(); name = $1 }
  {
    n++; ri[n] = $5; fu[n] = $7; le3 += ($7 <= 3.0)
    for (i = 8; i + 1 <= NF; i += 2) {
      k = $i; if (!(k in bn)) names[++nb] = k
      bn[k]++; bv[k, bn[k]] = $(i + 1)
      bok[k] += (k == "embree" ? $(i + 1) >= 20 : $(i + 1) >= 30)
    }
  }
  END { flush() }'
