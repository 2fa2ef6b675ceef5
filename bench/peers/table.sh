#!/bin/sh
# table.sh RECORDS [ABOUT]: the medians of run_peers.sh's records.tsv as Markdown tables.
# RECORDS columns: code bed np rep kind(bed|empty) atoms steps loop_s builds dangerous
#                  contacts_per_particle code_MB_per_rank rss_kB_summed_over_ranks
# Rate = atoms*steps/loop_s; net bytes per particle = (rss(bed) - rss(empty)) * 1024 /
# (atoms(bed) - atoms(empty)), paired by repetition, then the median over the repetitions that did
# not count contacts if there are any (the count allocates a neighbour list); the "empty" bed
# holds one sphere: LIGGGHTS does not run with none.
set -eu
[ $# -ge 1 ] || { echo "usage: $0 records.tsv [about.txt]" >&2; exit 2; }
if [ $# -ge 2 ] && [ -f "$2" ]; then sed 's/^/    /' "$2"; echo; fi
awk -F'\t' '
function median(a, n,   i, j, t) {
  for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
  return (n % 2) ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
}
function stat(what, k, kind,   i, n, a, lo, hi) {   # median of a column over the repetitions
  n = 0
  for (i = 1; i <= cnt[k]; i++) {
    if (what == "rate") a[++n] = rate[k, i]
    else if (what == "cpp" && cpp[k, i] != "-") a[++n] = cpp[k, i]
    else if (what == "builds" && bld[k, i] != "-") a[++n] = bld[k, i]
    else if (what == "mem" && mem[k, i] != "-") a[++n] = mem[k, i]
    else if (what == "net" && (k, rep[k, i]) in rsse && (cpp[k, i] == "-" || !uncounted[k]))
      a[++n] = (rssb[k, i] - rsse[k, rep[k, i]]) * 1024 / (atoms[k] - atomse[k, rep[k, i]])
  }
  if (n == 0) return "-"
  lo = hi = a[1]; for (i = 2; i <= n; i++) { if (a[i] < lo) lo = a[i]; if (a[i] > hi) hi = a[i] }
  spread = (what == "rate") ? sprintf("%.2f–%.2f", lo, hi) : ""
  return median(a, n)
}
$5 == "bed" {
  k = $1 SUBSEP $2 SUBSEP $3; i = ++cnt[k]
  rate[k, i] = $6 * $7 / $8 / 1e6; cpp[k, i] = $11; bld[k, i] = $9; mem[k, i] = $12
  rssb[k, i] = $13; rep[k, i] = $4; atoms[k] = $6; steps[k] = $7; nrep[k] = i
  if ($11 == "-") uncounted[k] = 1
}
$5 == "empty" { rsse[$1, $2, $3, $4] = $13; atomse[$1, $2, $3, $4] = $6 }
END {
  nc = split("adem adem_base lammps liggghts", codes, " ")
  name["adem"] = "adem"; name["adem_base"] = "adem (base)"; name["lammps"] = "LAMMPS"; name["liggghts"] = "LIGGGHTS"
  nb = split("hertz jkr", beds, " "); bname["hertz"] = "Hertz"; bname["jkr"] = "JKR"
  np_n = split("1 2 4 8", nps, " ")
  print "| bed | ranks/threads | code | runs | M particle-steps/s (median) | min–max | contacts/particle | neighbour builds | net B/particle | code MB/rank |"
  print "|---|---|---|---|---|---|---|---|---|---|"
  for (b = 1; b <= nb; b++) for (p = 1; p <= np_n; p++) for (c = 1; c <= nc; c++) {
    k = codes[c] SUBSEP beds[b] SUBSEP nps[p]
    if (!(k in cnt)) continue
    r = stat("rate", k); sp = spread; med[k] = r
    cc = stat("cpp", k); bb = stat("builds", k); nn = stat("net", k); mm = stat("mem", k)
    printf "| %s | %s | %s | %d | %.3f | %s | %s | %s | %s | %s |\n", bname[beds[b]], nps[p], name[codes[c]], cnt[k], r, sp,
      (cc == "-" ? "-" : sprintf("%.3f", cc)), bb, (nn == "-" ? "-" : sprintf("%.0f", nn)), (mm == "-" ? "-" : sprintf("%.1f", mm))
  }
  print ""
  print "| case | adem | adem (base) | LAMMPS | LIGGGHTS | adem / faster peer | base / faster peer | adem / base |"
  print "|---|---|---|---|---|---|---|---|"
  for (b = 1; b <= nb; b++) for (p = 1; p <= np_n; p++) {
    row = ""; any = 0; best = 0
    for (c = 1; c <= nc; c++) {
      k = codes[c] SUBSEP beds[b] SUBSEP nps[p]
      if (k in med) { row = row sprintf(" %.2f |", med[k]); any = 1; if (codes[c] !~ /^adem/ && med[k] > best) best = med[k] }
      else row = row " – |"
    }
    if (!any) continue
    ka = "adem" SUBSEP beds[b] SUBSEP nps[p]
    kb = "adem_base" SUBSEP beds[b] SUBSEP nps[p]
    ratio = ((ka in med) && best > 0) ? sprintf("%.2f", med[ka] / best) : "–"
    rbase = ((kb in med) && best > 0) ? sprintf("%.2f", med[kb] / best) : "–"
    rab = ((ka in med) && (kb in med)) ? sprintf("%.2f", med[ka] / med[kb]) : "–"
    printf "| %s bed, %s |%s %s | %s | %s |\n", bname[beds[b]], nps[p], row, ratio, rbase, rab
  }
  print ""
  for (b = 1; b <= nb; b++) {
    line = ""
    for (c = 1; c <= nc; c++) {
      k1 = codes[c] SUBSEP beds[b] SUBSEP 1; k2 = codes[c] SUBSEP beds[b] SUBSEP 2
      if ((k1 in med) && (k2 in med)) line = line sprintf(" %s %.2f×;", name[codes[c]], med[k2] / med[k1])
    }
    if (line != "") printf "Scaling 1 → 2, %s bed:%s\n", bname[beds[b]], line
  }
}' "$1"
