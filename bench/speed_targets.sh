#!/usr/bin/env bash
# Measures the simulation-speed targets of docs/PERFORMANCE.md, one after the
# other, and prints one line per figure with the load average around it:
#   1. the paper's full sweep (bunny, sportscar, conference x ICCs 1/4/16/32/48
#      x FIFO 10/100/1000, 64x64, 16x16 shadow groups), front end included,
#      event mode with the trace functional mode (cycle counts identical to
#      the netlist's, which steps every block every cycle), --jobs = cores;
#   2. ICC-cycles per second of the timing model, conference and bunny at 48
#      ICCs, FIFO 1000, event mode, both functional modes;
#   3. (--big) conference at 256 ICCs and 512x512 pixels: wall time and peak
#      memory (/usr/bin/time -v), about 15 minutes on 2 cores;
#   4. (--hd) the real-resolution frames, config paper, 256 ICCs, FIFO 1000,
#      exact event mode in the default functional mode, streamed: conference at
#      1920x1080 and 1280x720, bunny and sports car at 1920x1080; front end
#      and model wall time apart, their CPU time and waits (the JSON's wall),
#      peak memory, load (hours on 2 cores: see
#      docs/PERFORMANCE.md). --hd-sample F: the same frames with
#      sim.estimate = sample_passes, fraction F, and --sample-front-end
#      (minutes). With --hd or --hd-sample only these frames are run.
#      --hd-jobs N: the exact frames with simulate --jobs N (N shard processes
#      fed by one front end, docs/SHARDING.md); then the peak memory is the
#      whole process tree's, summed every 2 s. --hd-frame SCENE:WxH (repeatable):
#      only these frames (e.g. conference:1920x1080).
# The front end against Embree is bench/bench_frontend.cpp (see PERFORMANCE.md).
# --reading both|any: the Triangle Selector reading (icc.triangle_select;
# default: the config's, any).
#   bench/speed_targets.sh [--big] [--hd | --hd-sample F | --hd-jobs N] [--hd-frame SCENE:WxH]...
#                          [--reading both|any] [build/raplas]
set -euo pipefail
cd "$(dirname "$0")/.."
big=0
hd=0
hd_sample=()
hd_jobs=()
frames=("conference 1920 1080" "conference 1280 720" "bunny 1920 1080" "sportscar 1920 1080")
picked=()
raplas=build/raplas
reading=any
while [[ $# -gt 0 ]]; do
  case $1 in
    --big) big=1 ;;
    --hd) hd=1 ;;
    --hd-sample) hd=1; hd_sample=(--set sim.estimate=sample_passes --set "sim.sample_fraction=$2" --sample-front-end); shift ;;
    --hd-jobs) hd=1; hd_jobs=(--jobs "$2"); shift ;;
    --hd-frame)
      [[ $2 =~ ^([a-z_]+):([0-9]+)x([0-9]+)$ ]] || { echo "speed_targets.sh: --hd-frame wants SCENE:WxH, got '$2'" >&2; exit 2; }
      picked+=("${BASH_REMATCH[1]} ${BASH_REMATCH[2]} ${BASH_REMATCH[3]}"); shift ;;
    --reading) reading=$2; shift ;;
    *) raplas=$1 ;;
  esac
  shift
done
sel=(--set "icc.triangle_select=$reading")
echo "reading: $reading"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
load() { cut -d' ' -f1 /proc/loadavg; }
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print($2)" "$1"; }

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"

# 1. full paper sweep
if [[ $hd == 0 ]]; then
l0=$(load)
start=$(date +%s.%N)
"$raplas" sweep --scene scenes/bunny.toml --scene scenes/sportscar.toml --scene scenes/conference.toml \
  --config paper --iccs 1,4,16,32,48 --fifo 10,100,1000 --set sim.functional=trace "${sel[@]}" \
  --out "$work/paper.csv" >/dev/null 2>&1
end=$(date +%s.%N)
echo "paper sweep (45 points, front end included): $(python3 -c "print(f'{$end - $start:.1f}')") s wall" \
     "(load $l0 before, $(load) after)"

# 2. timing model speed at 48 ICCs
for scene in bunny conference; do
  "$raplas" trace --scene scenes/$scene.toml --triangle-select "$reading" --out "$work/$scene.trace" -q
  for fm in trace compute; do
    best=0
    for rep in 1 2 3; do
      "$raplas" simulate --trace "$work/$scene.trace" --config paper --iccs 48 --fifo 1000 \
        --set sim.functional=$fm "${sel[@]}" --json "$work/s.json" -q
      v=$(json "$work/s.json" "d['wall']['sim_icc_cycles_per_second']")
      best=$(python3 -c "print(max($best, $v))")
    done
    echo "$scene 48 ICCs FIFO 1000 event/$fm: $(python3 -c "print(f'{$best:.3g}')") ICC-cycles/s" \
         "(best of 3, load $(load))"
  done
done

fi

# 3. conference at 256 ICCs, 512 x 512
if [[ $big == 1 ]]; then
  l0=$(load)
  /usr/bin/time -v "$raplas" simulate --scene scenes/conference.toml "${sel[@]}" --set image.width=512 \
    --set image.height=512 --config paper --iccs 256 --fifo 1000 --set sim.functional=trace \
    --json "$work/big.json" -q 2>"$work/time.txt"
  rss=$(awk -F: '/Maximum resident/ {print $2}' "$work/time.txt" | xargs)
  wall=$(awk -F': ' '/Elapsed/ {print $2}' "$work/time.txt")
  echo "conference 512x512, 256 ICCs: $(json "$work/big.json" "d['total_cycles']") cycles," \
       "$wall wall, peak RSS $(python3 -c "print(f'{$rss / 1048576:.2f}')") GiB (load $l0 before, $(load) after)"
fi

# 4. real-resolution frames
if [[ $hd == 1 ]]; then
  [[ ${#picked[@]} -gt 0 ]] && frames=("${picked[@]}")
  for frame in "${frames[@]}"; do
    read -r scene w h <<<"$frame"
    l0=$(load)
    /usr/bin/time -v "$raplas" simulate --scene "scenes/$scene.toml" "${sel[@]}" --set "image.width=$w" \
      --set "image.height=$h" --config paper --iccs 256 --fifo 1000 "${hd_sample[@]}" "${hd_jobs[@]}" \
      --json "$work/hd.json" -q 2>"$work/time.txt" &
    run=$!
    if [[ ${#hd_jobs[@]} -gt 0 ]]; then
      # The process tree's resident size (time's pid, raplas under it, its shards), every 2 s.
      echo 0 >"$work/tree.kib"
      while kill -0 $run 2>/dev/null; do
        t=$(ps -eo pid,ppid,rss | awk -v r=$run '$2==r {p[$1]=1} {rss[$1]=$3; pp[$1]=$2}
              END {s=0; for (i in rss) if (p[i] || p[pp[i]]) s+=rss[i]; print s}')
        (( t > $(cat "$work/tree.kib") )) && echo "$t" >"$work/tree.kib"
        sleep 2
      done
    fi
    wait $run
    rss=$(awk -F: '/Maximum resident/ {print $2}' "$work/time.txt" | xargs)
    wall=$(awk -F': ' '/Elapsed/ {print $2}' "$work/time.txt")
    if [[ ${#hd_jobs[@]} -gt 0 ]]; then
      cpu=$(awk -F': ' '/User time|System time/ {s+=$2} END {printf "%.0f", s}' "$work/time.txt")
      echo "$scene ${w}x$h, 256 ICCs, ${hd_jobs[*]}: $(json "$work/hd.json" "d['total_cycles']") cycles" \
           "($(json "$work/hd.json" "round(d['time_ms'], 1)") ms at 400 MHz), $wall wall, $cpu s CPU," \
           "the longest shard's model $(json "$work/hd.json" "round(d['wall']['model_s_max'])") s; peak RSS" \
           "$(python3 -c "print(f'{$(cat "$work/tree.kib") / 1024:.0f}')") MiB (process tree, sampled; this process" \
           "$(python3 -c "print(f'{$rss / 1024:.0f}')") MiB) (load $l0 before, $(load) after)"
      continue
    fi
    echo "$scene ${w}x$h, 256 ICCs${hd_sample:+ (sampled)}: $(json "$work/hd.json" "d['total_cycles']") cycles" \
         "($(json "$work/hd.json" "round(d['time_ms'], 1)") ms at 400 MHz), $wall wall" \
         "(front end $(json "$work/hd.json" "round(d['wall']['frontend_s'])") s, model" \
         "$(json "$work/hd.json" "round(d['wall']['model_s'])") s, overlapping), peak RSS" \
         "$(python3 -c "print(f'{$rss / 1024:.0f}')") MiB (load $l0 before, $(load) after);" \
         "$(json "$work/hd.json" "'CPU s: model %.0f, loads %.0f, front end %.0f; waited s: model %.0f for groups, %.0f for loads, front end %.0f' % tuple(d['wall'][k] for k in ('model_cpu_s', 'loads_cpu_s', 'frontend_cpu_s', 'model_waits_s', 'load_waits_s', 'frontend_waits_s'))")"
  done
fi
