#!/usr/bin/env bash
# Compares the ADD(-S) < 4 cm of two tags of out/seeds/summary.tsv (scripts/accuracy_seeds.sh):
# each tag's seeds, mean, standard deviation and standard error, then the difference of the
# means A - B with its standard error sqrt(SE_A^2 + SE_B^2) (the seeds of the two runs are
# independent: the filters' random paths part after the first weights that differ) and its
# 90 % and 95 % intervals (Welch: Student's t with the Welch-Satterthwaite degrees of freedom,
# its quantile from the Cornish-Fisher expansion, good to 0.01 for 5 or more degrees of
# freedom). "Within 1 point" holds at the 5 % level of the two one-sided tests when the 90 %
# interval lies inside (-1, +1).
# Usage: scripts/accuracy_compare.sh TAG_A TAG_B [summary.tsv]
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
SUMMARY=${3:-out/seeds/summary.tsv}
[ -e "$SUMMARY" ] || { echo "accuracy_compare: $SUMMARY is missing" >&2; exit 1; }
awk -F'\t' -v a="$1" -v b="$2" '
  # Student t quantile from the normal one z (Cornish-Fisher, three terms).
  function tq(z, nu) { return z + (z^3 + z) / (4 * nu) + (5 * z^5 + 16 * z^3 + 3 * z) / (96 * nu^2) }
  $1 == a || $1 == b { n[$1]++; x[$1] += $3; xx[$1] += $3 * $3 }
  END {
    for (k = 0; k < 2; k++) {
      t = k == 0 ? a : b
      if (n[t] < 2) { printf "accuracy_compare: %s has %d seeds (at least 2 needed)\n", t, n[t] > "/dev/stderr"; exit 1 }
      m[t] = x[t] / n[t]; sd = sqrt((xx[t] - n[t] * m[t] * m[t]) / (n[t] - 1)); se[t] = sd / sqrt(n[t])
      printf "%-20s %3d seeds  mean %5.1f  SD %4.1f  SE %4.2f\n", t, n[t], m[t], sd, se[t]
    }
    d = m[a] - m[b]; s = sqrt(se[a] ^ 2 + se[b] ^ 2)
    nu = s ^ 4 / (se[a] ^ 4 / (n[a] - 1) + se[b] ^ 4 / (n[b] - 1))
    t90 = tq(1.6449, nu); t95 = tq(1.9600, nu)
    printf "%s - %s: %+.2f points, SE %.2f, %.0f degrees of freedom; 90 %% interval [%+.2f, %+.2f]; 95 %% interval [%+.2f, %+.2f]\n",
           a, b, d, s, nu, d - t90 * s, d + t90 * s, d - t95 * s, d + t95 * s
    if (nu < 5) printf "(fewer than 5 degrees of freedom: the t quantiles above are too small; add seeds)\n"
    within = (d - t90 * s > -1 && d + t90 * s < 1)
    printf "within 1 point (90 %% interval inside (-1, +1)): %s\n", within ? "yes" : "not shown"
  }' "$SUMMARY"
