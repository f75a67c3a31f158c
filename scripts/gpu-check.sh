#!/usr/bin/env bash
# The real-GPU check: one script, run once when a machine with a GPU is there, on release
# builds made elsewhere (docs/measurements.md, "On a real GPU", has what it gave).
#
#   cargo build --release --bin lampshade --example gpucheck
#   scripts/gpu-check.sh [BIN_DIR [OUT_DIR [SECONDS]]]
#
# BIN_DIR holds `lampshade` and `gpucheck` (default target/release, the example found in its
# examples/ folder too); OUT_DIR gets a log per step, summary.txt and gpu-check.tar.gz of it
# all (default gpu-check); SECONDS bounds the whole run (default 480): each step is cut at its
# own limit or at what is left, and the steps run in the order of what matters most, so a run
# cut short still has the capability table, the reference comparison and the smaller counts.
#
# Environment: GPU_CHECK_ADAPTER (default nvidia: a part of the adapter's name, so that a
# machine without it fails loudly instead of measuring lavapipe), GPU_CHECK_SIZE (default
# 1920x1080), GPU_CHECK_COUNTS (default "1024 16384 100000"), GPU_CHECK_FRAMES (default 5),
# GPU_CHECK_STEPS (a bash regular expression the step names must match, default every step).
#
# Steps:
#   adapters      `lampshade adapters`: every adapter's capability table
#   references    the `gpucheck` example: every stored reference configuration against
#                 lavapipe's PNG under the cross-CPU tolerance, and every culling mode against
#                 fullscreen on nine scenes on this adapter (the culling tests' one step)
#   culling-S-N   `lampshade bench S --only culling --lights N` at GPU_CHECK_SIZE, for
#                 S in demo, sphere-wall and N in GPU_CHECK_COUNTS: every mode's ms and FLIP
#   lights-S      `lampshade bench S --only lights`: the light-count sweep, every mode
#   shadows       `lampshade bench demo --only shadows`: budgets, kernels, cascades, formats
#                 and the cube layouts (face pick, seed 002's indirection, cube array)
#   references-gl the `gpucheck` comparisons again on wgpu's GL backend
set -u
bin=${1:-target/release}
out=${2:-gpu-check}
budget=${3:-480}
adapter=${GPU_CHECK_ADAPTER:-nvidia}
size=${GPU_CHECK_SIZE:-1920x1080}
counts=${GPU_CHECK_COUNTS:-1024 16384 100000}
frames=${GPU_CHECK_FRAMES:-5}
steps=${GPU_CHECK_STEPS:-.*}
check=$bin/gpucheck
[ -x "$check" ] || check=$bin/examples/gpucheck
mkdir -p "$out"
summary=$out/summary.txt
start=$(date +%s)

# step NAME LIMIT COMMAND...: runs COMMAND into OUT/NAME.log within LIMIT seconds or what is
# left of the budget, and notes its exit status and time in summary.txt.
step() {
    local name=$1 limit=$2
    shift 2
    [[ $name =~ ^($steps)$ ]] || return 0
    local left=$((budget - ($(date +%s) - start)))
    ((left < limit)) && limit=$left
    if ((limit < 10)); then
        echo "$name: skipped, the budget is spent" | tee -a "$summary"
        return
    fi
    local t0
    t0=$(date +%s)
    timeout -k 5 "$limit" "$@" >"$out/$name.log" 2>&1
    local rc=$?
    local note=""
    ((rc == 124 || rc == 137)) && note=" (cut at its ${limit} s limit)"
    echo "$name: exit $rc after $(($(date +%s) - t0)) s$note" | tee -a "$summary"
}

{
    echo "gpu-check $(date -u +%FT%TZ): adapter '$adapter', $size, counts $counts, $frames frames, budget $budget s"
    uname -a
    command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
} >"$summary" 2>&1

step adapters 30 "$bin/lampshade" adapters
step references 120 "$check" --adapter "$adapter" --out "$out/images"
for n in $counts; do
    for scene in demo sphere-wall; do
        step "culling-$scene-$n" 150 "$bin/lampshade" bench "$scene" --adapter "$adapter" --only culling \
            --size "$size" --lights "$n" --frames "$frames" --out "$out/culling-$scene-$n"
    done
done
for scene in demo sphere-wall; do
    step "lights-$scene" 150 "$bin/lampshade" bench "$scene" --adapter "$adapter" --only lights \
        --size "$size" --frames "$frames" --out "$out/lights-$scene"
done
step shadows 90 "$bin/lampshade" bench demo --adapter "$adapter" --only shadows \
    --size "$size" --frames "$frames" --out "$out/shadows"
# The same comparisons on wgpu's GL backend (EGL), the backend the suite checks on llvmpipe.
step references-gl 90 "$check" --adapter "$adapter" --backend gl --out "$out/images-gl"
tail -n 1 "$out/references.log" >>"$summary" 2>/dev/null
tar -czf "$out/gpu-check.tar.gz" -C "$out" --exclude gpu-check.tar.gz . 2>/dev/null
echo "gpu-check: done after $(($(date +%s) - start)) s" | tee -a "$summary"
