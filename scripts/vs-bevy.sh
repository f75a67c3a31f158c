#!/usr/bin/env bash
# Lampshade against Bevy, app frame against app frame, on the same glTF and the same adapter:
# peers/bevy/README.md says what each side renders and what still differs.
#
#   scripts/vs-bevy.sh --check
#       `cargo metadata --locked` in peers/bevy: its lock file still resolves (a guard against
#       rot; nothing is built).
#   scripts/vs-bevy.sh [--layout sphere-wall|many-lights] [--counts 64,256,1024,4096]
#                      [--size 1280x720] [--rounds 2] [--warmup 60] [--frames 300]
#                      [--bevy deferred-gpu,deferred-cpu,forward-gpu,forward-cpu]
#                      [--culling auto] [--out DIR] [--no-build] [--tables-only]
#
# It builds both apps in release, writes the layout's glTF at each count (sphere-wall:
# ../shared/peers/sphere_wall.py; many-lights: peers/bevy/many_lights.py), and at each count runs
# Lampshade's viewer and each Bevy variant in turn, --rounds times (A B C … A B C …), each run
# `--warmup` frames and then `--frames`/`--rounds` timed ones, under one X server. Lampshade is
# the viewer with its panels hidden at `--scale 1`, its window made taller by its top bar and
# status line so that the scene is rendered at exactly `--size`, as Bevy's window is. Bevy's
# variants: the renderer method (deferred, forward) and its light clustering on the GPU or the
# CPU. Each frame's wall delta is kept: Lampshade's frame log (`--frame-log`), Bevy's printed
# line per frame.
#
# `--tables-only` writes the tables again from DIR's runs without running anything.
#
# It writes DIR/table.md (the medians of the pooled frames, their 10th to 90th percentile, the
# ratios to the faster clustering of each Bevy method) and DIR/breakdown.md (Lampshade's GPU
# passes per count), and prints both. DIR defaults to target/vs-bevy/LAYOUT.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
peer="$root/peers/bevy"

layout=sphere-wall counts=64,256,1024,4096 size=1280x720 rounds=2 warmup=60 frames=300
bevy=deferred-gpu,deferred-cpu,forward-gpu,forward-cpu culling=auto out="" build=1 run=1
while [ $# -gt 0 ]; do
    case "$1" in
        --check)
            cd "$peer"
            cargo metadata --locked --format-version 1 >/dev/null
            echo "peers/bevy: Cargo.lock resolves"
            exit 0 ;;
        --layout) layout=$2; shift ;;
        --counts) counts=$2; shift ;;
        --size) size=$2; shift ;;
        --rounds) rounds=$2; shift ;;
        --warmup) warmup=$2; shift ;;
        --frames) frames=$2; shift ;;
        --bevy) bevy=$2; shift ;;
        --culling) culling=$2; shift ;;
        --out) out=$2; shift ;;
        --no-build) build=0 ;;
        --tables-only) build=0 run=0 ;;
        -h|--help) sed -n '2,31p' "$0"; exit 0 ;;
        *) echo "vs-bevy: unknown argument '$1' (--help)" >&2; exit 2 ;;
    esac
    shift
done
case "$layout" in sphere-wall|many-lights) ;; *) echo "vs-bevy: --layout is sphere-wall or many-lights" >&2; exit 2 ;; esac
[[ "$size" =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "vs-bevy: --size '$size' is not WxH" >&2; exit 2; }
w=${BASH_REMATCH[1]} h=${BASH_REMATCH[2]}
for n in rounds warmup frames; do
    [[ "${!n}" =~ ^[1-9][0-9]*$ ]] || { echo "vs-bevy: --$n '${!n}' is not a positive whole number" >&2; exit 2; }
done
[[ "$counts" =~ ^[1-9][0-9]*(,[1-9][0-9]*)*$ ]] || { echo "vs-bevy: --counts '$counts' is not N,N,…" >&2; exit 2; }
for v in ${bevy//,/ }; do
    case "$v" in deferred-gpu|deferred-cpu|forward-gpu|forward-cpu) ;; *) echo "vs-bevy: unknown Bevy variant '$v'" >&2; exit 2 ;; esac
done
per_run=$(( (frames + rounds - 1) / rounds ))
out=${out:-$root/target/vs-bevy/$layout}

# One X server for every run, large enough for Lampshade's window (the scene plus its bars).
if [ -z "${DISPLAY:-}" ] && [ $run = 1 ]; then
    exec xvfb-run -a -s "-screen 0 $((w + 64))x$((h + 200))x24" "$0" --layout "$layout" --counts "$counts" \
        --size "$size" --rounds "$rounds" --warmup "$warmup" --frames "$frames" --bevy "$bevy" \
        --culling "$culling" --out "$out" $([ $build = 0 ] && echo --no-build)
fi
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp/xdg-$(id -u)}
mkdir -p "$XDG_RUNTIME_DIR" "$out"

if [ $build = 1 ]; then
    (cd "$root" && cargo build --release --locked --bin lampshade)
    (cd "$peer" && cargo build --release --locked)
fi
if [ $run = 1 ]; then
    ls_bin="$root/target/release/lampshade"
    bevy_bin="$peer/target/release/lampshade-vs-bevy"
    for b in "$ls_bin" "$bevy_bin"; do [ -x "$b" ] || { echo "vs-bevy: $b is not built" >&2; exit 1; }; done

    gltf() { # COUNT -> the layout's glTF at that count
        local f="$out/$layout-$1.gltf"
        if [ ! -f "$f" ]; then
            if [ "$layout" = sphere-wall ]; then
                python3 "$root/../shared/peers/sphere_wall.py" "$1" "$f" >/dev/null
            else
                python3 "$peer/many_lights.py" "$1" "$f" >/dev/null
            fi
        fi
        echo "$f"
    }

    # Lampshade's bars: a short run at --size reads the scene's size from the frame log.
    ls_script() { # FRAMES FILE
        {
            echo "1 set panel-left off"
            echo "1 set panel-right off"
            echo "1 set panel-gbuffer off"
            echo "1 culling $culling"
            echo "$1 quit"
        } >"$2"
    }
    first=$(gltf "${counts%%,*}")
    ls_script 3 "$out/probe.script"
    "$ls_bin" view "$first" --size "$size" --scale 1 --no-state --script "$out/probe.script" \
        --frame-log "$out/probe.jsonl" >"$out/probe.log" 2>&1
    bar=$(python3 -c "import json,sys; l=[json.loads(x) for x in open(sys.argv[1])]; print($h - l[-1]['size'][1])" "$out/probe.jsonl")
    ls_size="${w}x$((h + bar))"
    echo "Lampshade's window: $ls_size (its bars take $bar px), the scene at $size"
    ls_script $((warmup + per_run)) "$out/run.script"

    for n in ${counts//,/ }; do
        f=$(gltf "$n")
        for r in $(seq 1 "$rounds"); do
            echo "== $n lights, round $r of $rounds"
            "$ls_bin" view "$f" --size "$ls_size" --scale 1 --no-state --script "$out/run.script" \
                --frame-log "$out/lampshade-$n-$r.jsonl" >"$out/lampshade-$n-$r.log" 2>&1 \
                || { echo "vs-bevy: Lampshade failed, see $out/lampshade-$n-$r.log" >&2; exit 1; }
            for v in ${bevy//,/ }; do
                "$bevy_bin" "$f" --size "$size" --method "${v%-*}" --gpu-clustering "$([ "${v#*-}" = gpu ] && echo on || echo off)" \
                    --warmup "$warmup" --frames "$per_run" >"$out/bevy-$v-$n-$r.txt" 2>"$out/bevy-$v-$n-$r.log" \
                    || { echo "vs-bevy: Bevy failed, see $out/bevy-$v-$n-$r.log" >&2; exit 1; }
            done
        done
    done
fi

python3 - "$out" "$counts" "$rounds" "$warmup" "$per_run" "$bevy" "$size" "$layout" <<'EOF'
import json, statistics, sys, glob, os, re
out, counts, rounds, warmup, per_run, bevy, size, layout = sys.argv[1:]
counts = [int(c) for c in counts.split(",")]
rounds, warmup, per_run = int(rounds), int(warmup), int(per_run)
variants = bevy.split(",")

def q(xs, p):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(p * (len(xs) - 1) + 0.5))]

scene_size = [int(x) for x in size.split("x")]

def lampshade(n):
    lines = []
    for r in range(1, rounds + 1):
        for x in open(f"{out}/lampshade-{n}-{r}.jsonl"):
            l = json.loads(x)
            if warmup < l["frame"] <= warmup + per_run:
                if l["config"] is None or l["stand_in"]:
                    sys.exit(f"Lampshade frame {l['frame']} at {n} lights drew no configuration")
                if l["size"] != scene_size:
                    sys.exit(f"Lampshade frame {l['frame']} at {n} lights was {l['size']}, not {scene_size}")
                lines.append(l)
    if len(lines) != rounds * per_run:
        sys.exit(f"Lampshade at {n} lights: {len(lines)} timed frames, not {rounds * per_run}")
    return lines

# Bevy's frame K counts from the first of its frames with the scene loaded and no pipeline
# compiling (peers/bevy/src/main.rs); the timed ones must stay so.
LINE = re.compile(r"frame (\d+) app \d+ wall_ms ([\d.]+) gpu_clustering (on|off) lights (\d+) cameras (\d+) pending (\d+)")

def bevy_frames(v, n):
    ms, gpu = [], set()
    for r in range(1, rounds + 1):
        for x in open(f"{out}/bevy-{v}-{n}-{r}.txt"):
            m = LINE.match(x)
            if m and warmup < int(m[1]) <= warmup + per_run:
                ms.append(float(m[2])); gpu.add(m[3])
                if (int(m[4]), int(m[5]), int(m[6])) != (n, 1, 0):
                    sys.exit(f"Bevy {v} frame {m[1]}: {m[4]} lights, {m[5]} cameras, {m[6]} pipelines compiling")
    return ms, gpu

def cell(xs):
    return f"{statistics.median(xs):.1f} ({q(xs, 0.1):.1f}–{q(xs, 0.9):.1f})"

rows, brk = [], []
head = ["lights", "Lampshade ms", "mode"] + [f"Bevy {v} ms" for v in variants]
methods = sorted({v.split("-")[0] for v in variants}, key=lambda m: m != "deferred")
head += [f"Bevy {m} / Lampshade" for m in methods]
for n in counts:
    ls = lampshade(n)
    ls_ms = [l["wall_ms"] for l in ls]
    modes = {}
    for l in ls:
        for k, c in (l.get("methods") or {}).items():
            modes[k] = max(modes.get(k, 0), c)
    culling = sorted({l["config"].split(" · ")[1] for l in ls})
    row = [f"{n:,}", cell(ls_ms), ", ".join(culling) + ": " + ", ".join(f"{k} {c:,}" for k, c in sorted(modes.items()))]
    best = {}
    for v in variants:
        ms, gpu = bevy_frames(v, n)
        if len(ms) != rounds * per_run:
            sys.exit(f"Bevy {v} at {n} lights: {len(ms)} timed frames, not {rounds * per_run}")
        want = "on" if v.endswith("gpu") else "off"
        if gpu != {want}:
            sys.exit(f"Bevy {v} at {n} lights ran with GPU clustering {gpu}")
        row.append(cell(ms))
        m = v.split("-")[0]
        best[m] = min(best.get(m, float("inf")), statistics.median(ms))
    lm = statistics.median(ls_ms)
    row += [f"{best[m] / lm:.2f}×" for m in methods]
    rows.append(row)
    med = lambda k: statistics.median([(l["passes"] or {}).get(k) or 0.0 for l in ls])
    keys = ["gbuffer", "lighting", "lists", "compose", "tonemap", "total"]
    brk.append([f"{n:,}"] + [f"{med(k):.1f}" for k in keys]
               + [f"{statistics.median([l['gpu_ms'] or 0 for l in ls]):.1f}",
                  f"{statistics.median([l['render_ms'] for l in ls]):.1f}", f"{lm:.1f}"])

def table(head, rows):
    s = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n"
    return s + "".join("| " + " | ".join(r) + " |\n" for r in rows)

t = (f"{layout}, {size}, {rounds} interleaved rounds of {warmup} + {per_run} frames a side "
     f"(medians of {rounds * per_run} frames, 10th–90th percentile in brackets)\n\n" + table(head, rows))
b = ("Lampshade's GPU passes, medians over the same frames (ms; `lists` is part of `lighting`)\n\n"
     + table(["lights", "G-buffer", "lighting", "lists", "compose", "tonemap", "GPU total", "GPU (log)",
              "viewer thread", "app frame"], brk))
open(f"{out}/table.md", "w").write(t)
open(f"{out}/breakdown.md", "w").write(b)
print(t); print(b)
EOF
