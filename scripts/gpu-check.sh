#!/usr/bin/env bash
# The real-GPU check: one script, run once when a machine with a GPU is there, on release
# builds made elsewhere (docs/measurements.md, "On a real GPU", has what it gave).
#
#   cargo build --release --bin lampshade --example gpucheck --example pipecache
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
# 1920x1080), GPU_CHECK_COUNTS (default "1024 16384 100000": the culling steps' counts),
# GPU_CHECK_REGRET_COUNTS (default "64,256,1024,4096,16384": the regret steps' `lights` group),
# GPU_CHECK_SCALE_COUNTS (default "100000": the scale rows), GPU_CHECK_FRAMES (default 5),
# GPU_CHECK_STEPS (a bash regular expression the step names must match, default every step).
# A lavapipe rehearsal within the budget: GPU_CHECK_ADAPTER=llvmpipe GPU_CHECK_SIZE=320x180
# GPU_CHECK_COUNTS=1024 GPU_CHECK_REGRET_COUNTS=64,1024 GPU_CHECK_SCALE_COUNTS=16384
# GPU_CHECK_FRAMES=5.
#
# Steps, in the order of what matters most:
#   adapters      `lampshade adapters`: every adapter's capability table
#   calibrate     `lampshade calibrate`: the cost model's constants on this adapter (written to
#                 OUT/calibration.json and the user's cache, which the later steps read)
#   gbuffer-S     `lampshade bench S --only gbuffer`: the G-buffer span split (an empty scene's
#                 clears, one triangle, the scene with and without timestamps and debug groups,
#                 a bare wgpu pass clearing the same targets), for S in demo, sphere-wall
#   regret-S      `lampshade bench S --only lights`: every mode at the regret counts, the report's
#                 "`auto`'s regret" table, for S in demo, sphere-wall, railings, street
#   ledger        `lampshade bench demo --only ledger --lights 60 --size 640x360 --frames 15`:
#                 each mode's ten costliest lights removed one at a time, predicted against saved
#   culling-S-N   `lampshade bench S --only culling --lights N`: every mode's ms and FLIP, the
#                 culling share (`culling_share`) and the stricter limit (`limit_ratio`), for S
#                 in demo, sphere-wall and N in GPU_CHECK_COUNTS
#   references    the `gpucheck` example: every stored reference configuration against
#                 lavapipe's PNG under the cross-CPU tolerance, and every culling mode against
#                 fullscreen on nine scenes on this adapter (the culling tests' one step)
#   scale-S       `lampshade bench S --only lights --counts GPU_CHECK_SCALE_COUNTS`: the scale
#                 rows (ns per ideal pair past 65,536 lights; no brute force above 10^5 lights:
#                 the bench's error reference is `volume` there)
#   shadows       `lampshade bench demo --only shadows`: budgets, kernels, cascades, formats
#                 and the cube layouts (face pick, seed 002's indirection, cube array)
#   references-gl the `gpucheck` comparisons again on wgpu's GL backend
#   pipeline-cache the `pipecache` example twice on one cache file: four configurations'
#                 pipelines created cold, then warm from the driver's saved pipeline cache
#   camera-path   `lampshade bench demo --camera-path assets/paths/demo.json`: tiled, clustered,
#                 zbin and auto replayed along the demo's path: p50/p95/p99 frame time, the worst
#                 frame and where, the flicker
#   renderdoc     where `renderdoccmd` is installed: the viewer under RenderDoc, F11 on frame 5;
#                 the capture's XML export is searched for the frame's debug groups (`shadows`,
#                 `gbuffer`, `lights`, `compose`); where it is not, the step says so
#   stochastic    `lampshade bench sphere-wall --only stochastic`: RIS (K = 1 to 16) and
#                 stochastic culling against the exact modes and the engines' caps over the
#                 eleven layouts; stochastic.md gives per layout the first K at FLIP 0.05 and its
#                 time against the fastest exact mode: the crossover on this adapter
#   restir-N      `lampshade bench sphere-wall --only restir --quick --lights N`: the equal-time
#                 comparison on a moving camera (RIS with one sample, reuse off or spatial and
#                 temporal, the denoiser off or on, against clustered and zbin) at 10^5 and 10^6
#                 lights, in ns a pixel beside Helio's 1.05 (no brute force: the exact frame is
#                 clustered's)
set -u
bin=${1:-target/release}
out=${2:-gpu-check}
budget=${3:-480}
adapter=${GPU_CHECK_ADAPTER:-nvidia}
size=${GPU_CHECK_SIZE:-1920x1080}
counts=${GPU_CHECK_COUNTS:-1024 16384 100000}
regret_counts=${GPU_CHECK_REGRET_COUNTS:-64,256,1024,4096,16384}
scale_counts=${GPU_CHECK_SCALE_COUNTS:-100000}
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
step calibrate 60 "$bin/lampshade" calibrate --adapter "$adapter" --out "$out/calibration.json"
cal=()
[ -f "$out/calibration.json" ] && cal=(--calibration "$out/calibration.json")
for scene in demo sphere-wall; do
    step "gbuffer-$scene" 45 "$bin/lampshade" bench "$scene" --adapter "$adapter" --only gbuffer \
        --size "$size" --out "$out/gbuffer-$scene"
done
for scene in demo sphere-wall railings street; do
    step "regret-$scene" 90 "$bin/lampshade" bench "$scene" --adapter "$adapter" --only lights \
        --counts "$regret_counts" --size "$size" --frames "$frames" "${cal[@]}" --out "$out/regret-$scene"
done
step ledger 90 "$bin/lampshade" bench demo --adapter "$adapter" --only ledger --lights 60 \
    --size 640x360 --frames 15 "${cal[@]}" --out "$out/ledger"
for n in $counts; do
    for scene in demo sphere-wall; do
        step "culling-$scene-$n" 90 "$bin/lampshade" bench "$scene" --adapter "$adapter" --only culling \
            --size "$size" --lights "$n" --frames "$frames" "${cal[@]}" --out "$out/culling-$scene-$n"
    done
done
step references 120 "$check" --adapter "$adapter" --out "$out/images"
for scene in demo sphere-wall; do
    step "scale-$scene" 120 "$bin/lampshade" bench "$scene" --adapter "$adapter" --only lights \
        --counts "$scale_counts" --size "$size" --frames "$frames" "${cal[@]}" --out "$out/scale-$scene"
done
step stochastic 150 "$bin/lampshade" bench sphere-wall --adapter "$adapter" --only stochastic \
    --size "$size" --frames "$frames" "${cal[@]}" --out "$out/stochastic"
for n in 100000 1000000; do
    step "restir-$n" 150 "$bin/lampshade" bench sphere-wall --adapter "$adapter" --only restir --quick \
        --lights "$n" --size "$size" "${cal[@]}" --out "$out/restir-$n"
done
step shadows 90 "$bin/lampshade" bench demo --adapter "$adapter" --only shadows \
    --size "$size" --frames "$frames" --out "$out/shadows"
step camera-path 90 "$bin/lampshade" bench demo --adapter "$adapter" --camera-path assets/paths/demo.json \
    --modes tiled,clustered,zbin,auto --size "$size" "${cal[@]}" --out "$out/camera-path"
# RenderDoc's capture through wgpu's hooks (F11), and whether it carries the debug groups.
renderdoc() {
    command -v renderdoccmd >/dev/null || {
        echo "renderdoccmd is not installed: no capture checked"
        return 0
    }
    local dir=$out/renderdoc
    mkdir -p "$dir"
    printf '1 set shadows none\n5 key F11\n9 quit\n' >"$dir/capture.script"
    local run=()
    [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null && run=(xvfb-run -a)
    "${run[@]}" renderdoccmd capture -w -c "$dir/frame" "$bin/lampshade" view demo --adapter "$adapter" \
        --script "$dir/capture.script" --no-state || return 1
    local cap
    cap=$(ls "$dir"/frame*.rdc 2>/dev/null | head -n 1)
    [ -n "$cap" ] || { echo "no capture written"; return 1; }
    renderdoccmd convert -f "$cap" -o "$dir/frame.zip.xml" -c zip.xml || return 1
    unzip -p "$dir/frame.zip.xml" 2>/dev/null | grep -o -E '"(shadows|gbuffer|lights|compose)[^"]*"' | sort -u | head -n 20
}
export -f renderdoc
export out bin adapter
step renderdoc 60 bash -c renderdoc
# The same comparisons on wgpu's GL backend (EGL), the backend the suite checks on llvmpipe.
step references-gl 90 "$check" --adapter "$adapter" --backend gl --out "$out/images-gl"
# The pipeline cache the viewer keeps between runs: cold, then warm.
pipecache=$bin/pipecache
[ -x "$pipecache" ] || pipecache=$bin/examples/pipecache
rm -f "$out/pipelines.bin"
step pipeline-cache-cold 30 "$pipecache" "$out/pipelines.bin" "$adapter"
step pipeline-cache-warm 30 "$pipecache" "$out/pipelines.bin" "$adapter"
# The answers the first questions want, gathered into the summary.
{
    tail -n 1 "$out/references.log"
    [ -f "$out/renderdoc.log" ] && echo "renderdoc: $(tr '\n' ' ' <"$out/renderdoc.log" | cut -c1-300)"
    [ -f "$out/camera-path/path.md" ] && sed -n '/^| configuration/,/^$/p' "$out/camera-path/path.md"
    for f in "$out"/pipeline-cache-*.log; do
        [ -f "$f" ] && echo "$(basename "$f" .log): $(tail -n 1 "$f")"
    done
    for f in "$out"/regret-*/bench.md; do
        [ -f "$f" ] && echo "$(basename "$(dirname "$f")"): $(grep -o 'Met at [0-9]* of [0-9]* points' "$f")"
    done
    for f in "$out"/gbuffer-*/bench.md; do
        [ -f "$f" ] && echo "$(basename "$(dirname "$f")"):" && sed -n '/^| case |/,/^$/p' "$f"
    done
} >>"$summary" 2>/dev/null
tar -czf "$out/gpu-check.tar.gz" -C "$out" --exclude gpu-check.tar.gz . 2>/dev/null
echo "gpu-check: done after $(($(date +%s) - start)) s" | tee -a "$summary"
