#!/usr/bin/env bash
# Builds Candela and runs every check CI runs, timing each stage (README "Tests";
# docs/robustness.md has the details and measured times):
#   1. checks    no build: scripts/check-format.sh (every C++ file as clang-format makes it with
#                .clang-format), scripts/gen-plugin-docs.py --check (docs/plugins/ matches the
#                plugins' opening comments) and scripts/check-include-deps.py (every #include
#                crosses only to folders whose targets the including target links);
#   2. release   Release build, the whole test suite through ctest;
#   3. asan      clang build with AddressSanitizer + UndefinedBehaviorSanitizer (and libFuzzer's
#                coverage, so that the fuzzers come from the same build): the unit and CLI tests
#                under them, the statistical ones at CANDELA_TEST_EFFORT=0.1 (tests/util.h), the
#                end-to-end verification against references (renders at the sample counts their
#                fixed tolerances need) and the real-Slurm farm left to the release stage
#                (release_only);
#   4. tsan      clang build with ThreadSanitizer: the tests of the parallel paths (parallel_paths
#                below) but those left to the release stage (release_only);
#   5. fuzz      every libFuzzer target for FUZZ_SECONDS (default 45) each, two at a time.
# A sanitizer report fails the test that caused it (every finding is fatal: core/
# sanitizer_options.cpp). All five run by default, as CI runs them; STAGES selects some
# ("checks" alone, "checks release", ...).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
jobs=$(nproc)
stages=${STAGES:-checks release asan tsan fuzz}
fuzz_seconds=${FUZZ_SECONDS:-45}
summary=()

stage() {
    local name=$1
    shift
    local start=$SECONDS
    echo "== ci: $name"
    "$@"
    summary+=("$(printf '%-8s %4d s' "$name" $((SECONDS - start)))")
}

# Both checks run even when the first fails, so that one run names everything to fix.
checks() {
    local failed=0
    ./scripts/check-format.sh || failed=1
    python3 scripts/gen-plugin-docs.py --check || failed=1
    python3 scripts/check-include-deps.py || failed=1
    return "$failed"
}

# The three build directories share one folder of RGB-to-spectrum tables (cmake/
# srgb_sigmoid_table.cmake), so the first configure computes the table and the others reuse it.
tables="-DCANDELA_SRGB_SIGMOID_DIR=$PWD/build-tables"

release() {
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=ON "$tables"
    cmake --build build -j"$jobs"
    ctest --test-dir build --output-on-failure --timeout 1500 -j"$jobs"
}

# Run in the release stage only: the whole-scene verification against references with fixed
# tolerances (and the error trends that come with them), and the agreements between estimators
# with a stated power (the spectral and polarized light tracers against path, radiosity in
# scalar_spectral against path, the raster mode's physical settings against path), which need
# their full sample counts while the sanitizers see the same code in smaller tests ("light paths:"
# runs sppm and photonmapper with 1 and 2 threads, "radiosity: bit-identical" the solver and its
# final gather, "every integrator renders with every sampler in the spectral variants" each
# integrator in scalar_spectral and scalar_spectral_polarized, "raster: " and "rasterizer: " the
# raster mode); and the real-Slurm farm test, which drives the candela program through sbatch
# while the sanitizers see the program's farm code in the "farm cli:" tests.
release_only='^(validate|converge|sppm: agrees|photonmapper: the Cornell box|radiosity: the Cornell box agrees|radiosity: the smooth display|radiosity: in scalar_spectral the Cornell box agrees|spectral: (photonmapper agrees|photonmapper.s binned|ptracer.s and sppm.s)|polarized: ptracer.s light paths|raster: physical settings)|^farm\.slurm$'

asan() {
    CXX=clang++ cmake -S . -B build-asan -DCANDELA_FUZZ=ON -DBUILD_TESTING=ON "$tables"
    cmake --build build-asan -j"$jobs" --target candela candela_tests
    CANDELA_TEST_EFFORT=0.1 ctest --test-dir build-asan --output-on-failure --timeout 1500 -j"$jobs" -E "$release_only"
}

# The tests that run the parallel code (every tbb::parallel_for of the sources): the pixel loop
# (integrator and CLI renders, crops, AOVs, Ctrl-C), the rasterizer's tiles, per-vertex lighting,
# ambient occlusion and environment prefiltering, the OBJ reader's chunks ("obj: "), the serialized
# reader's follower thread and PLY's parallel parse ("serialized: a large mesh" reads both), the light
# tree's build and its use by the render threads, the photon passes of sppm and photonmapper and
# ptracer's splats ("light paths:" renders them with 1 and 2 threads), the radiosity solver, and
# the estimators of `candela estimate`. Check a change with: ctest --test-dir build -N -R "$parallel_paths" -E "$release_only".
parallel_paths='^(determinism|obj: |serialized: a large mesh equals|film: a crop|render: AOVs|cli: render|cli: Ctrl-C|cli: estimate|raster: |rasterizer: |raster AO: deterministic|raster IBL: |light tree|light samplers|light paths: |radiosity: bit-identical|radiosity and ao: |ao: bit-identical|furnace: |example scenes|scenes/shapes|null transport)'

tsan() {
    CXX=clang++ cmake -S . -B build-tsan -DCANDELA_SANITIZE=thread -DBUILD_TESTING=ON "$tables"
    cmake --build build-tsan -j"$jobs" --target candela candela_tests
    CANDELA_TEST_EFFORT=0.1 ctest --test-dir build-tsan --output-on-failure --timeout 1500 -j"$jobs" -R "$parallel_paths" -E "$release_only"
}

fuzz() {
    cmake --build build-asan -j"$jobs" --target fuzzers
    ./scripts/fuzz.sh build-asan "$fuzz_seconds"
}

for s in $stages; do stage "$s" "$s"; done
echo "== ci: stage times"
printf '%s\n' "${summary[@]}"
echo "total    $SECONDS s"
