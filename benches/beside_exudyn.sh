#!/usr/bin/env bash
# axle beside Exudyn on the same 500-case McPherson path, run alternately on
# this machine: the per-case and whole-process ratios of docs/performance.md.
#
#   benches/beside_exudyn.sh PEER_DIR [ROUNDS]
#
# PEER_DIR is Exudyn's model of the benchmark McPherson (`mcpherson.py` and
# `loads/random_500.csv`; its README says how to install Exudyn). PYTHON
# names the interpreter that has Exudyn (default: PEER_DIR/.venv/bin/python,
# else python3). ROUNDS (default 4) alternate the two; each round prints:
#
# - a case: Exudyn's median solve time a case (its own timer: load set-up
#   and static solve) beside axle's median case on the same CSV (the
#   `statics` bench's prologue, `AXLE_BENCH_LOADS`: 21 runs of each case),
#   and their ratio;
# - the whole process: CPU time of Exudyn's run (start-up, build and the
#   path) and of `axle solve examples/mcpherson.axle --loads CSV --format
#   json`, medians of 3 and of 20 runs, and their ratio;
#
# then the rounds' median ratios.
#
# Only ratios measured side by side carry over from one machine to another.
set -euo pipefail
[ $# -ge 1 ] || {
    echo "usage: benches/beside_exudyn.sh PEER_DIR [ROUNDS]" >&2
    exit 2
}
[ -d "$1" ] || {
    echo "$1: no such directory (PEER_DIR: Exudyn's model of the McPherson, relative to where you are)" >&2
    exit 2
}
peer=$(cd "$1" && pwd)
rounds=${2:-4}
cd "$(dirname "$0")/.."
loads="$peer/loads/random_500.csv"
[ -f "$peer/mcpherson.py" ] && [ -f "$loads" ] || {
    echo "$peer has no mcpherson.py and loads/random_500.csv" >&2
    exit 2
}
py=${PYTHON:-$peer/.venv/bin/python}
[ -x "$py" ] || py=python3

echo "building axle and the statics bench (minutes on a fresh clone) ..." >&2
# (The binaries' paths from cargo: a CARGO_TARGET_DIR moves them.)
axle=$(cargo build --release --locked --message-format=json 2>/dev/null |
    sed -n 's/.*"executable":"\([^"]*\/axle\)".*/\1/p' | tail -n 1)
[ -x "$axle" ] || {
    echo "axle did not build" >&2
    exit 1
}
bench=$(cargo bench --bench statics --no-run --locked --message-format=json 2>/dev/null |
    sed -n 's/.*"executable":"\([^"]*statics-[^"]*\)".*/\1/p' | tail -n 1)
[ -x "$bench" ] || {
    echo "the statics bench did not build" >&2
    exit 1
}

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# CPU milliseconds of one run of the command, its output dropped: perf's
# task-clock where perf runs (the figures of docs/performance.md), else the
# shell's user and system times (whose resolution is the kernel's tick on
# many machines: a few milliseconds, too coarse for axle's run alone).
if perf stat -x, -e task-clock true > /dev/null 2>&1; then
    cpu_ms() {
        perf stat -x, -e task-clock -- "$@" 2>&1 > /dev/null | awk -F, '/task-clock/ {print $1}'
    }
else
    echo "perf is not available: CPU times by the shell's clock" >&2
    cpu_ms() {
        local TIMEFORMAT='%3U %3S'
        { time "$@" > /dev/null 2>&1; } 2>&1 | awk '{printf "%.2f\n", 1000 * ($1 + $2)}'
    }
fi

exudyn_case() {
    (cd "$peer" && "$py" mcpherson.py --loads "$loads" --bushing native --quiet) |
        sed -n 's/^median solve time per case \([0-9.]*\) ms.*/\1/p'
}

axle_case() {
    AXLE_BENCH_LOADS="$loads" "$bench" --bench nothing 2>/dev/null |
        sed -n 's/.*(500 cases) per case.*median case \([0-9.]*\) µs.*/\1/p'
}

rows=$(mktemp)
trap 'rm -f "$rows"' EXIT
echo "machine: $(nproc) CPUs, $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1)"
echo "round | Exudyn a case (ms) | axle a case (µs) | ratio | Exudyn process (ms) | axle process (ms) | ratio"
for r in $(seq 1 "$rounds"); do
    exu=$(exudyn_case) || true
    [ -n "$exu" ] || {
        echo "Exudyn's run printed no median: does $py have exudyn (PYTHON=...)?" >&2
        exit 1
    }
    ax=$(axle_case) || true
    [ -n "$ax" ] || {
        echo "the statics bench printed no median case for $loads" >&2
        exit 1
    }
    exu_proc=$(for _ in 1 2 3; do cpu_ms "$py" "$peer/mcpherson.py" --loads "$loads" --bushing native --quiet; done | median)
    ax_proc=$(for _ in $(seq 1 20); do cpu_ms "$axle" solve examples/mcpherson.axle --loads "$loads" --format json; done | median)
    awk -v r="$r" -v e="$exu" -v a="$ax" -v ep="$exu_proc" -v ap="$ax_proc" \
        'BEGIN {printf "%d | %.4f | %.2f | %.1f | %.0f | %.2f | %.1f\n", r, e, a, 1000 * e / a, ep, ap, ep / ap}'
done | tee "$rows"
# The rounds' median ratios: a slow spell on one side moves one round, not these.
awk -F' [|] ' '{print $4}' "$rows" | median | awk '{printf "median ratio a case: %.1f\n", $1}'
awk -F' [|] ' '{print $7}' "$rows" | median | awk '{printf "median ratio whole process: %.1f\n", $1}'
