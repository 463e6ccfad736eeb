#!/usr/bin/env bash
# The cost of splitting a render (issue 13): total CPU time (user + system) of N parts plus their
# merge against one render of the same image, for N = 1, 4, 16; the merge's peak memory against
# the size of one image of sums and one part; and that the merged image equals the single one.
# It prints figures and asserts nothing.
#
# Usage: bench/bench_farm.sh [CANDELA] [RES] [SPP]     (defaults: build/candela 256 256)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
candela=${1:-$here/build/candela}
res=${2:-256}
spp=${3:-256}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/candela-bench-farm.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
scene="$here/scenes/cbox.xml"
opts=(-D "res=$res" --spp "$spp" --seed 1 --aov variance --threads 1 --quiet)

# Runs a command under GNU time; prints "user+sys seconds" and "max RSS kB" into $tmp/t.
timed() { /usr/bin/time -f "%U %S %M" -o "$tmp/t" "$@"; read -r u s m < "$tmp/t"; cpu=$(echo "$u + $s" | bc); rss=$m; }

echo "Cornell box ${res}x${res}, $spp spp, one thread per part"
timed "$candela" render "$scene" "${opts[@]}" -o "$tmp/single.exr"
single=$cpu
printf "one render:          %8.2f s CPU, %7d kB peak\n" "$single" "$rss"
for n in 1 4 16; do
  total=0
  mkdir -p "$tmp/p$n"
  for ((k = 0; k < n; ++k)); do
    timed "$candela" render "$scene" "${opts[@]}" --samples "$((k * spp / n)):$(((k + 1) * spp / n))" -o "$tmp/p$n/part-$k.exr"
    total=$(echo "$total + $cpu" | bc)
  done
  part_bytes=$(stat -c %s "$tmp/p$n/part-0.exr")
  timed "$candela" merge "$tmp/p$n" -o "$tmp/merged$n.exr"
  merge_cpu=$cpu
  merge_rss=$rss
  total=$(echo "$total + $merge_cpu" | bc)
  same=$("$candela" compare "$tmp/merged$n.exr" "$tmp/single.exr" --pixel-tolerance 1 | awk '/max pixel/ {print "against one render: max rel. diff " $5}')
  printf "N = %2d: parts + merge %8.2f s CPU (%.3fx one render); merge %.2f s, %d kB peak; part file %d kB; %s\n" \
    "$n" "$total" "$(echo "$total / $single" | bc -l)" "$merge_cpu" "$merge_rss" "$((part_bytes / 1024))" "$same"
done
# Memory: the merge holds the image's sums (4 doubles per pixel for R, G, B and the weight, plus
# 152 bytes of pixel statistics with AOVs) and one part (float32 channels) at a time.
echo "sums of one image: $((res * res * (4 * 8 + 152) / 1024)) kB; a part in memory: $((res * res * 16 * 4 / 1024)) kB"
