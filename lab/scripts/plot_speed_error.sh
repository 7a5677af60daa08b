#!/bin/sh
# Redraws the speed-against-error plot from a CSV written by `shellcontract bench error --csv`
# (the same plot as its --plot option), without rerunning the ladder.
#   usage: lab/scripts/plot_speed_error.sh RESULTS.csv OUT.png|OUT.svg [TITLE]
# Needs gnuplot (Debian: gnuplot-nox, installed by scripts/install_deps.sh).
set -eu
if [ $# -lt 2 ]; then
  echo "usage: $0 RESULTS.csv OUT.png|OUT.svg [TITLE]" >&2
  exit 1
fi
csv=$1
out=$2
title=${3:-$(basename "$csv")}
command -v gnuplot >/dev/null 2>&1 || { echo "$0: gnuplot is not installed (apt-get install gnuplot-nox)" >&2; exit 1; }
[ -r "$csv" ] || { echo "$0: cannot read $csv" >&2; exit 1; }
case $out in
  *.svg) terminal="svg size 900,640 dynamic font 'sans,12'" ;;
  *.png) terminal="pngcairo size 900,640 font 'sans,11'" ;;
  *) echo "$0: output must end in .png or .svg" >&2; exit 1 ;;
esac
# One line per (solver, substeps, order, threads) among the rungs, in file order (columns:
# row_type, solver, iterations, substeps, ..., ms_per_step = 8, hausdorff = 9, ..., order = 14,
# threads = 15; files from before the order column count as sequential, 1 thread).
series=$(awk -F, '$1 == "rung" { o = ($14 == "" ? "sequential" : $14); t = ($15 == "" ? 1 : $15); if (!seen[$2 "," $4 "," o "," t]++) print $2 "," $4 "," o "," t }' "$csv")
has_order=$(head -n 1 "$csv" | grep -c ',order,' || true)
plot=""
colours=""
for s in $series; do
  IFS=, read -r solver sub order threads <<EOF_SERIES
$s
EOF_SERIES
  # One colour per (solver, substeps); order and threads in the line and point style, as
  # `bench error --plot` draws them.
  case " $colours " in *" $solver,$sub "*) ;; *) colours="$colours $solver,$sub" ;; esac
  lt=1
  for c in $colours; do [ "$c" = "$solver,$sub" ] && break; lt=$((lt + 1)); done
  pt=7; dt=1
  if [ "$order" != sequential ]; then if [ "$threads" = 1 ]; then pt=5; dt=2; else pt=9; dt=3; fi; fi
  if [ "$sub" = 1 ]; then unit=substep; else unit=substeps; fi
  label="$solver, $sub $unit"
  if [ "$has_order" = 0 ]; then
    osel="1"
  elif [ "$order" = sequential ]; then
    osel="(strcol(14) eq 'sequential')"
  else
    osel="(strcol(14) eq '$order' && \$15 == $threads)"
    if [ "$threads" = 1 ]; then label="$label, $order 1 thread"; else label="$label, $order $threads threads"; fi
  fi
  sel="(strcol(1) eq 'rung' && strcol(2) eq '$solver' && \$4 == $sub && $osel && \$9 > 0 ? \$9 : 1/0)"
  plot="$plot'$csv' skip 1 using 8:$sel with linespoints lt $lt dt $dt pt $pt title '$label', '$csv' skip 1 using 8:$sel:3 with labels offset char 0.8,0.6 font ',8' tc lt $lt notitle, "
done
ref="(strcol(1) eq 'reference_check' && \$9 > 0 ? \$9 : 1/0)"
plot="$plot'$csv' skip 1 using 8:$ref with points pt 3 ps 2 lc rgb 'black' title 'each reference vs its refinement (its own error)', '$csv' skip 1 using 8:$ref:(strcol(2).' reference') with labels offset char 0,-1 font ',8' notitle"
gnuplot <<GP
set terminal $terminal
set output '$out'
set datafile separator ','
set logscale xy
set grid
set key below
set xlabel 'wall time per step (ms, median)'
set ylabel 'Hausdorff distance to the reference (normalized units)'
set title '$title' noenhanced
plot $plot
GP
