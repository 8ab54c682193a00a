#!/usr/bin/env bash
# The fuzzing campaign's figures as a Markdown table, from the per-run log that
# scripts/fuzz.sh appends to (default build-san/fuzz-log.tsv; the campaign's own log is
# committed as fuzz/campaign.tsv). Every run of a target starts from the corpus the earlier
# runs left, so the figures add up: runs, wall and CPU time, executions and findings are
# sums; coverage and corpus size are those at the end of the target's last run.
# Usage: scripts/fuzz-report.sh [LOG.tsv]
set -euo pipefail
log=${1:-build-san/fuzz-log.tsv}
[ -r "$log" ] || { echo "fuzz-report: cannot read $log" >&2; exit 1; }
awk -F'\t' '
  NF < 7 { next }
  {
    t = $1
    if (!(t in runs)) order[++n] = t
    runs[t]++; wall[t] += $2; cpu[t] += ($3 == "?" ? 0 : $3)
    execs[t] += ($4 == "?" ? 0 : $4); cov[t] = $5; corpus[t] = $6
    if ($7 != "ok") findings[t]++
  }
  function thousands(x,   s) {
    s = sprintf("%.0f", x)
    while (s ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]([,]|$)/, ",&", s)
    return s
  }
  END {
    print "| target | runs | wall | CPU | CPU-hours | executions | coverage (edges) | corpus | findings |"
    print "|---|---|---|---|---|---|---|---|---|"
    for (i = 1; i <= n; i++) {
      t = order[i]
      printf "| `%s` | %d | %d min | %d min | %.2f | %s | %s | %s | %d |\n", t, runs[t],
             wall[t] / 60, cpu[t] / 60, cpu[t] / 3600, thousands(execs[t]), cov[t], corpus[t],
             findings[t] + 0
      tcpu += cpu[t]; texecs += execs[t]; tf += findings[t]
    }
    printf "| all | | | %d min | %.2f | %s | | | %d |\n", tcpu / 60, tcpu / 3600, thousands(texecs), tf
  }' "$log"
