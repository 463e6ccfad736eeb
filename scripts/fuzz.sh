#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build (cmake -DCANDELA_FUZZ=ON, see docs/robustness.md,
# "Sanitizers and fuzzing") for a fixed time each, as many at once as there are cores.
#
#   scripts/fuzz.sh [BUILD_DIR] [SECONDS]      (defaults: build-fuzz, 60)
#
# Each target starts from its seeds in fuzz/corpus/NAME (never written to) and a fresh working
# corpus in BUILD_DIR/fuzz/run/NAME. libFuzzer's random seed is fixed (-seed=1), but the run is
# bounded by time, so how many inputs it tries, and which, differs between machines: a run proves
# nothing about inputs it did not try. The exit code is non-zero only for what libFuzzer found (a
# sanitizer report, a crash or an uncaught exception, a time-out of one input, an allocation or a
# resident size beyond the limits); the input that did it is saved as
# BUILD_DIR/fuzz/run/NAME-crash-*, -timeout-* or -oom-*, and the command to replay it is printed.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
seconds=${2:-60}
list="$build/fuzz/fuzzers.txt"
[ -f "$list" ] || { echo "fuzz: $list not found (configure with -DCANDELA_FUZZ=ON and build the target 'fuzzers')" >&2; exit 2; }
mapfile -t lines < "$list"
run="$build/fuzz/run"
rm -rf "$run"
mkdir -p "$run"

# One input may take at most 15 s (the scenes render at most 32 x 32 pixels at 1 spp); one
# allocation at most 1 GiB, the whole process 2 GiB.
# A target's own options (fuzz/CMakeLists.txt) come later and win; NAME=value ones go to the
# environment.
fuzz_one() {
    local name=$1
    shift
    local flags=() environment=()
    for option in "$@"; do
        if [[ $option == -* ]]; then flags+=("$option"); else environment+=("$option"); fi
    done
    mkdir -p "$run/$name"
    local limits=(-timeout=15 -rss_limit_mb=2048 -malloc_limit_mb=1024) status=0
    env "${environment[@]}" "$build/fuzz/fuzz_$name" -seed=1 -max_total_time="$seconds" "${limits[@]}" -print_final_stats=1 \
        -artifact_prefix="$run/$name-" "${flags[@]}" "$run/$name" "fuzz/corpus/$name" > "$run/$name.log" 2>&1 || status=$?
    # LeakSanitizer's check at exit stops every thread from a tracer, and clang 14's tracer itself
    # sometimes crashes ("Tracer caught signal 11", after libFuzzer's "Done N runs"; libFuzzer then
    # saves the empty input as a crash). That is a check that did not run, not a finding: it runs
    # again on a replay of the whole corpus (every input once, then the same exit check), which
    # must pass. A leak LeakSanitizer did find is reported as "detected memory leaks" instead.
    local attempt
    for attempt in 1 2 3; do
        [ "$status" -ne 0 ] && grep -q "^Tracer caught signal" "$run/$name.log" && grep -q "^Done [0-9]* runs" "$run/$name.log" &&
            ! grep -q "LeakSanitizer: detected memory leaks" "$run/$name.log" || break
        rm -f "$run/$name-crash-da39a3ee5e6b4b0d3255bfef95601890afd80709"  # the empty input
        status=0
        env "${environment[@]}" "$build/fuzz/fuzz_$name" -runs=0 "${limits[@]}" -artifact_prefix="$run/$name-" "${flags[@]}" \
            "$run/$name" "fuzz/corpus/$name" > "$run/$name.replay.log" 2>&1 || status=$?
        echo "fuzz.sh: LeakSanitizer's tracer crashed at exit; replay $attempt of the corpus: exit $status" >> "$run/$name.log"
        [ "$status" -eq 0 ] || { cat "$run/$name.replay.log" >> "$run/$name.log"; grep -q "^Tracer caught signal" "$run/$name.replay.log" || break; }
    done
    return "$status"
}

jobs=$(nproc)
pids=()
for line in "${lines[@]}"; do
    read -r -a words <<< "$line"
    [ ${#words[@]} -gt 0 ] || continue
    name=${words[0]}
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; done
    fuzz_one "${words[@]}" &
    pids+=("$!:$name")
done

failed=0
for entry in "${pids[@]}"; do
    pid=${entry%%:*}
    name=${entry#*:}
    status=0
    wait "$pid" || status=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$run/$name.log" | tail -1)
    corpus=$(find "$run/$name" -type f | wc -l)
    if [ "$status" -eq 0 ]; then
        replayed=$(grep -c "^fuzz.sh: LeakSanitizer's tracer crashed" "$run/$name.log" || true)
        note=""
        [ "$replayed" -eq 0 ] || note=" (LeakSanitizer's tracer crashed at exit; its check passed on replay $replayed of the corpus)"
        echo "fuzz: $name: ${runs:-?} inputs in ${seconds} s, ${corpus} new in the corpus, nothing found$note"
    else
        failed=1
        echo "fuzz: $name: FOUND A BUG (exit $status) after ${runs:-?} inputs; log: $run/$name.log"
        grep -E "^==[0-9]+==ERROR|runtime error|^SUMMARY|terminate called|what\(\)|ALARM|out-of-memory" "$run/$name.log" | head -5 | sed 's/^/    /'
        for artifact in "$run/$name"-*; do
            [ -e "$artifact" ] && echo "    replay: $build/fuzz/fuzz_$name $artifact"
        done
    fi
done
exit $failed
