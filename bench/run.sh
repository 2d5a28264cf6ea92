#!/usr/bin/env bash
# Throughput and memory of `osplint check` on generated CAM programs.
#
#     bench/run.sh [--osplint BIN] [--dir DIR] [--repeat N] [--sizes "1 10 100"]
#
# Builds osplint (Release, in DIR/build, unless --osplint names a binary) and
# the word-scan floor (bench/wordscan.cpp), generates the programs with
# bench/gen_cam.py (deterministic: the same bytes on every machine), and prints
# for each size: osplint's wall time, MB/s and peak RSS (`/usr/bin/time`), the
# floor's time and the ratio. Times are wall-clock times, the best of N runs
# (other processes may share the machine); the peak RSS is the largest of the
# runs. Then `-j 1`
# against `-j 2` on 100 files of 1 MB, and the targets:
#   * 100 MB at most 3x the floor's time,
#   * peak RSS at most 64 MB,
#   * linear scaling: the time per MB at 100 MB within 1.25x of the time per MB at 10 MB.
# Exit status 1 when a target is missed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${OSPLINT_BENCH_DIR:-$root/build-bench}
osplint=""
repeat=3
sizes="1 10 100"
while (($#)); do
  case $1 in
    --osplint) osplint=$(realpath "$2"); shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    *) echo "usage: bench/run.sh [--osplint BIN] [--dir DIR] [--repeat N] [--sizes \"1 10 100\"]" >&2; exit 2 ;;
  esac
done
[[ -x /usr/bin/time ]] || { echo "bench/run.sh: /usr/bin/time is required (Debian package 'time')" >&2; exit 2; }
mkdir -p "$dir"

if [[ -z $osplint ]]; then
  cmake -S "$root" -B "$dir/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  ninja -C "$dir/build" -j "${OSPLINT_BENCH_JOBS:-2}" osplint >/dev/null
  osplint="$dir/build/osplint"
fi
if [[ ! -x $dir/wordscan || $root/bench/wordscan.cpp -nt $dir/wordscan ]]; then
  c++ -O2 -o "$dir/wordscan" "$root/bench/wordscan.cpp"
fi

for s in $sizes; do
  f="$dir/CAM$s.MIN"
  [[ -f $f && $f -nt $root/bench/gen_cam.py ]] || python3 "$root/bench/gen_cam.py" --size-mb "$s" --seed 1 --output "$f"
done

# best_of N CMD...: "<best seconds> <largest peak RSS in KB>" over N runs.
best_of() {
  local n=$1; shift
  local best="" rss=0 t m
  for ((k = 0; k < n; k++)); do
    local start=$EPOCHREALTIME
    /usr/bin/time -f "%M" -o "$dir/time.out" "$@" >/dev/null 2>&1 || true
    local end=$EPOCHREALTIME
    t=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.3f", b - a}')
    read -r m <"$dir/time.out"
    if [[ -z $best ]] || awk "BEGIN{exit !($t < $best)}"; then best=$t; fi
    ((m > rss)) && rss=$m
  done
  echo "$best $rss"
}

echo "osplint: $osplint"
echo "machine: $(nproc) cores, $(uname -sr), load $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-8s %12s %10s %10s %12s %10s %8s\n' size bytes osplint_s MB/s peak_RSS_MB floor_s ratio
declare -A secs rss_of floor_of bytes_of
for s in $sizes; do
  f="$dir/CAM$s.MIN"
  cat "$f" >/dev/null  # in the page cache for both
  read -r t m < <(best_of "$repeat" "$osplint" check --format json "$f")
  read -r w _ < <(best_of "$repeat" "$dir/wordscan" "$f")
  b=$(stat -c %s "$f")
  secs[$s]=$t rss_of[$s]=$m floor_of[$s]=$w bytes_of[$s]=$b
  awk -v s="$s MB" -v b="$b" -v t="$t" -v m="$m" -v w="$w" 'BEGIN{
    mbs = t > 0 ? b / 1e6 / t : 0; ratio = w > 0 ? t / w : 0;
    printf "%-8s %12d %10.3f %10.1f %12.1f %10.3f %8.2f\n", s, b, t, mbs, m / 1024, w, ratio }'
done

# Parallel files: 100 programs of 1 MB.
help=$("$osplint" check --help 2>/dev/null || true)
if grep -q -- '--jobs' <<<"$help"; then
  many="$dir/many"
  if [[ ! -f $many/P099.MIN ]]; then
    mkdir -p "$many"
    for i in $(seq 0 99); do
      python3 "$root/bench/gen_cam.py" --size-mb 1 --seed $((i + 100)) --output "$many/P$(printf '%03d' "$i").MIN"
    done
  fi
  cat "$many"/*.MIN >/dev/null
  read -r t1 m1 < <(best_of "$repeat" "$osplint" check --format json -j 1 "$many")
  read -r t2 m2 < <(best_of "$repeat" "$osplint" check --format json -j 2 "$many")
  awk -v t1="$t1" -v t2="$t2" -v m1="$m1" -v m2="$m2" 'BEGIN{
    speedup = t2 > 0 ? t1 / t2 : 0
    printf "100 x 1 MB: -j 1 %.3f s (%.1f MB RSS), -j 2 %.3f s (%.1f MB RSS), speed-up %.2f\n",
      t1, m1 / 1024, t2, m2 / 1024, speedup }'
fi

# Targets (on the largest size, and the scaling from 10 MB to it).
status=0
last=${sizes##* }
check() {  # check NAME CONDITION-AWK-EXPRESSION
  if awk "BEGIN{exit !($2)}"; then echo "target met:    $1"; else echo "target missed: $1"; status=1; fi
}
check "$last MB within 3x the floor (${secs[$last]} s vs ${floor_of[$last]} s)" "${secs[$last]} <= 3 * ${floor_of[$last]}"
check "peak RSS at most 64 MB ($((rss_of[$last] / 1024)) MB)" "${rss_of[$last]} <= 64 * 1024"
if [[ -n ${secs[10]:-} && $last != 10 ]]; then
  check "linear scaling (s/MB at $last MB within 1.25x of 10 MB)" \
    "(${secs[$last]} / ${bytes_of[$last]}) <= 1.25 * (${secs[10]} / ${bytes_of[10]})"
fi
exit $status
