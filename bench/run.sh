#!/usr/bin/env bash
# Throughput and memory of `osplint check` on generated CAM programs of every
# shape, then the language server (bench/lsp_edit.cpp).
#
#     bench/run.sh [--osplint BIN] [--lsp-edit BIN] [--dir DIR] [--repeat N] [--sizes "1 10 100"]
#                  [--shapes "plain numbered loops travel bigloop macros"] [--no-lsp]
#
# Builds osplint and lsp_edit (Release, in DIR/build, unless --osplint names a
# binary: lsp_edit is then taken from the same directory, or --lsp-edit) and
# the word-scan floor (bench/wordscan.cpp), generates the programs with
# bench/gen_cam.py (deterministic: the same bytes on every machine; cached in
# DIR as SHAPE<size>.MIN, made again when gen_cam.py is newer; see gen_cam.py
# for the shapes), and prints a row for each shape and size: osplint's wall
# time, MB/s and peak RSS (`/usr/bin/time`), the floor's time on the same file
# and the ratio, and the findings. Times are wall-clock times, the best of N
# runs (other processes may share the machine); the peak RSS is the largest
# of the runs. `check --format json` for every shape, then again with the
# travel limits of DIR/travel.toml (row SHAPE+limits: a machine configured as
# users configure theirs, where every macro call and hole is also checked
# against the travel; no finding, the programs stay inside it); the travel shape (every
# Z below the Z travel of DIR/travel.toml, one finding per block) as folded by
# default, then in every output format with --fold 0, so that every finding
# is written (to /dev/null). Then `-j 1` against `-j 2` on 100 files of 1 MB, lsp_edit
# (unless --no-lsp; its edits on every shape given), and the targets, at the largest size:
#   * every shape, with and without the travel limits: at most 3x the floor's
#     time and a peak RSS of at most 64 MB
#     (travel: as folded by default; writing a million findings or more in full
#     is not a scan of the input);
#   * travel (1,000,000+ findings from 20 MB on): peak RSS at most 64 MB in every format;
#   * lsp_edit's: see bench/lsp_edit.cpp.
# Exit status 1 when a target is missed or a run fails (everything is printed first).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${OSPLINT_BENCH_DIR:-$root/build-bench}
osplint=""
lsp_edit=""
repeat=3
sizes="1 10 100"
shapes="plain numbered loops travel bigloop macros"
lsp=1
formats="text json sarif gcc github"
usage='usage: bench/run.sh [--osplint BIN] [--lsp-edit BIN] [--dir DIR] [--repeat N] [--sizes "1 10 100"]
                    [--shapes "plain numbered loops travel bigloop macros"] [--no-lsp]'
while (($#)); do
  case $1 in
    --osplint) osplint=$(realpath "$2"); shift 2 ;;
    --lsp-edit) lsp_edit=$(realpath "$2"); shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --shapes) shapes=$2; shift 2 ;;
    --no-lsp) lsp=0; shift ;;
    *) echo "$usage" >&2; exit 2 ;;
  esac
done
[[ -x /usr/bin/time ]] || { echo "bench/run.sh: /usr/bin/time is required (Debian package 'time')" >&2; exit 2; }
for shape in $shapes; do
  case $shape in plain | numbered | loops | travel | bigloop | macros) ;; *) echo "bench/run.sh: unknown shape $shape" >&2; exit 2 ;; esac
done
mkdir -p "$dir"
dir=$(realpath "$dir")
gen=$root/bench/gen_cam.py

targets=(osplint)
((lsp)) && targets+=(lsp_edit)
if [[ -z $osplint ]]; then
  cmake -S "$root" -B "$dir/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  ninja -C "$dir/build" -j "${OSPLINT_BENCH_JOBS:-2}" "${targets[@]}" >/dev/null
  osplint="$dir/build/osplint"
  [[ -n $lsp_edit ]] || lsp_edit="$dir/build/lsp_edit"
elif ((lsp)) && [[ -z $lsp_edit ]]; then
  lsp_edit="$(dirname "$osplint")/lsp_edit"
  [[ -x $lsp_edit ]] || { echo "bench/run.sh: no lsp_edit next to $osplint (--lsp-edit BIN or --no-lsp)" >&2; exit 2; }
fi
if [[ ! -x $dir/wordscan || $root/bench/wordscan.cpp -nt $dir/wordscan ]]; then
  c++ -O2 -o "$dir/wordscan" "$root/bench/wordscan.cpp"
fi

# A machine's travel (the Z stroke of examples/osplint.toml): the travel
# shape and the +limits rows (--config).
cat >"$dir/travel.toml" <<'EOF'
# bench/run.sh: a machine's travel. Every Z of the travel shape is below -300;
# the other shapes stay inside (their +limits rows).
[machine]
units = "mm"
plane = "G17"
[machine.travel]
x = [-560.0, 560.0]
y = [-460.0, 460.0]
z = [-300.0, 150.0]
EOF

# program SHAPE SIZE: the generated file (LOOPS100.MIN), made when missing or older than gen_cam.py.
program() {
  local f="$dir/${1^^}$2.MIN"
  if [[ ! -f $f || ! $f -nt $gen ]]; then
    local start=$EPOCHREALTIME
    python3 "$gen" --size-mb "$2" --seed 1 --shape "$1" --output "$f.tmp"
    mv "$f.tmp" "$f"
    awk -v a="$start" -v b="$EPOCHREALTIME" -v f="${f##*/}" 'BEGIN{printf "generated %s in %.1f s\n", f, b - a}' >&2
  fi
  echo "$f"
}

# Runs that failed, one line each (best_of runs in a subshell).
failures="$dir/failures"
: >"$failures"
# best_of OUT N CMD...: "<best seconds> <largest peak RSS in KB>" over N runs,
# the command's standard output in OUT (standard error is dropped). A run
# that dies of a signal or exits with more than 1 (1 means findings) is
# reported and fails the benchmark.
best_of() {
  local out=$1 n=$2; shift 2
  local best="" rss=0 t m x
  for ((k = 0; k < n; k++)); do
    local start=$EPOCHREALTIME
    /usr/bin/time -f "%x %M" -o "$dir/time.out" "$@" >"$out" 2>/dev/null || true
    local end=$EPOCHREALTIME
    t=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.3f", b - a}')
    if grep -q signal "$dir/time.out"; then
      echo "FAILED: $* ($(head -n 1 "$dir/time.out"))" | tee -a "$failures" >&2
    fi
    read -r x m < <(tail -n 1 "$dir/time.out")
    if ((x > 1)); then
      echo "FAILED: $* (exit status $x)" | tee -a "$failures" >&2
    fi
    if [[ -z $best ]] || awk "BEGIN{exit !($t < $best)}"; then best=$t; fi
    ((m > rss)) && rss=$m
  done
  echo "$best $rss"
}

# findings_json FILE: errors + warnings + infos of a JSON report ("?" when it cannot be read).
findings_json() {
  python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))["summary"]
print(s["error"] + s["warning"] + s["info"])' "$1" 2>/dev/null || echo "?"
}

row() {  # row NAME SIZE BYTES SECONDS RSS_KB FLOOR_SECONDS FINDINGS
  awk -v n="$1" -v s="$2 MB" -v b="$3" -v t="$4" -v m="$5" -v w="$6" -v f="$7" 'BEGIN{
    mbs = t > 0 ? b / 1e6 / t : 0; ratio = w > 0 ? t / w : 0;
    printf "%-16s %-7s %11d %10.3f %8.1f %12.1f %8.3f %7.2f %10s\n", n, s, b, t, mbs, m / 1024, w, ratio, f }'
}

for shape in $shapes; do
  for s in $sizes; do program "$shape" "$s" >/dev/null; done
done

echo "osplint: $osplint"
echo "machine: $(nproc) cores, $(uname -sr), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "check --format json (travel: folded as by default, then every format with --fold 0, to /dev/null); best of $repeat"
printf '%-16s %-7s %11s %10s %8s %12s %8s %7s %10s\n' shape size bytes osplint_s MB/s peak_RSS_MB floor_s ratio findings
declare -A secs rss_of floor_of findings_of
for shape in $shapes; do
  for s in $sizes; do
    f=$(program "$shape" "$s")
    b=$(stat -c %s "$f")
    cat "$f" >/dev/null  # in the page cache for both
    read -r w _ < <(best_of /dev/null "$repeat" "$dir/wordscan" "$f")
    floor_of[$shape,$s]=$w
    if [[ $shape != travel ]]; then
      read -r t m < <(best_of "$dir/report.json" "$repeat" "$osplint" check --format json "$f")
      secs[$shape,$s]=$t rss_of[$shape,$s]=$m
      row "$shape" "$s" "$b" "$t" "$m" "$w" "$(findings_json "$dir/report.json")"
      read -r t m < <(best_of "$dir/report.json" "$repeat" "$osplint" check --config "$dir/travel.toml" --format json "$f")
      secs[$shape+limits,$s]=$t rss_of[$shape+limits,$s]=$m floor_of[$shape+limits,$s]=$w
      row "$shape+limits" "$s" "$b" "$t" "$m" "$w" "$(findings_json "$dir/report.json")"
      continue
    fi
    # The count, from the summary line of a folded text report (small).
    n=$("$osplint" check --config "$dir/travel.toml" --format text "$f" 2>/dev/null | tail -n 1 | awk '{print $1}' || true)
    # As a user gets it (the first findings of each kind, the others counted):
    # what the time target is about. Then written in full, in every format.
    read -r t m < <(best_of /dev/null "$repeat" "$osplint" check --config "$dir/travel.toml" --format json "$f")
    secs[$shape,$s]=$t rss_of[$shape,$s]=$m
    row "travel:folded" "$s" "$b" "$t" "$m" "$w" "$n"
    for fmt in $formats; do
      read -r t m < <(best_of /dev/null "$repeat" "$osplint" check --config "$dir/travel.toml" --fold 0 --format "$fmt" "$f")
      secs[$shape:$fmt,$s]=$t rss_of[$shape:$fmt,$s]=$m
      row "travel:$fmt" "$s" "$b" "$t" "$m" "$w" "$n"
    done
    findings_of[$s]=$n
  done
done

# Parallel files: 100 programs of 1 MB.
help=$("$osplint" check --help 2>/dev/null || true)
if grep -q -- '--jobs' <<<"$help"; then
  many="$dir/many"
  if [[ ! -f $many/P099.MIN || $gen -nt $many/P099.MIN ]]; then
    mkdir -p "$many"
    for i in $(seq 0 99); do
      python3 "$gen" --size-mb 1 --seed $((i + 100)) --output "$many/P$(printf '%03d' "$i").MIN"
    done
  fi
  cat "$many"/*.MIN >/dev/null
  read -r t1 m1 < <(best_of /dev/null "$repeat" "$osplint" check --format json -j 1 "$many")
  read -r t2 m2 < <(best_of /dev/null "$repeat" "$osplint" check --format json -j 2 "$many")
  awk -v t1="$t1" -v t2="$t2" -v m1="$m1" -v m2="$m2" 'BEGIN{
    speedup = t2 > 0 ? t1 / t2 : 0
    printf "100 x 1 MB: -j 1 %.3f s (%.1f MB RSS), -j 2 %.3f s (%.1f MB RSS), speed-up %.2f\n",
      t1, m1 / 1024, t2, m2 / 1024, speedup }'
fi

lsp_status=0
if ((lsp)); then
  echo "lsp_edit: $lsp_edit"
  set +e
  "$lsp_edit" --dir "$dir" --gen "$gen" --edit-shapes "$shapes" | tee "$dir/lsp.out" | grep -v '^target'
  lsp_status=${PIPESTATUS[0]}
  set -e
  ((lsp_status <= 1)) || echo "FAILED: lsp_edit (exit status $lsp_status)" | tee -a "$failures"
fi

# Targets, at the largest size.
status=0
last=$(tr ' ' '\n' <<<"$sizes" | sort -g | tail -n 1)
echo "targets at $last MB:"
check() {  # check NAME CONDITION-AWK-EXPRESSION
  if awk "BEGIN{exit !($2)}"; then echo "target met:    $1"; else echo "target missed: $1"; status=1; fi
}
mb() { awk -v k="$1" 'BEGIN{printf "%.1f", k / 1024}'; }
rows=""
for shape in $shapes; do
  rows+=" $shape"
  [[ $shape != travel ]] && rows+=" $shape+limits"
done
for shape in $rows; do
  t=${secs[$shape,$last]} w=${floor_of[$shape,$last]} m=${rss_of[$shape,$last]}
  ratio=$(awk -v t="$t" -v w="$w" 'BEGIN{r = w > 0 ? t / w : 0; printf "%.1f", r}')
  what=$shape
  [[ $shape == travel ]] && what="travel (folded)"
  check "$what $last MB: at most 3x the floor ($t s vs $w s: ${ratio}x)" "$t <= 3 * $w"
  check "$shape $last MB: peak RSS at most 64 MB ($(mb "$m") MB)" "$m <= 64 * 1024"
  if [[ $shape == travel ]]; then
    for fmt in $formats; do
      m=${rss_of[$shape:$fmt,$last]}
      check "travel $last MB (${findings_of[$last]} findings), --format $fmt: peak RSS at most 64 MB ($(mb "$m") MB)" \
        "$m <= 64 * 1024"
    done
  fi
done
if ((lsp)); then
  grep '^target' "$dir/lsp.out" || true
  grep -q '^target missed' "$dir/lsp.out" && status=1
fi
if [[ -s $failures ]]; then
  echo "runs that failed:"
  cat "$failures"
  status=1
fi
# Not a target: how the time per MB grows from 10 MB to the largest size.
if [[ $last != 10 && " $sizes " == *" 10 "* ]]; then
  for shape in $shapes; do
    awk -v n="$shape" -v a="${secs[$shape,10]}" -v b="${secs[$shape,$last]}" -v l="$last" 'BEGIN{
      if (a > 0) printf "scaling (not a target): %s s/MB at %s MB = %.2fx s/MB at 10 MB\n", n, l, (b / l) / (a / 10) }'
  done
fi
exit $status
