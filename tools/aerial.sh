#!/usr/bin/env bash
# aerial.sh — sets up, builds and runs the project: the two commands of the README's Quick start.
#
#   tools/aerial.sh run    installs what is missing, builds, renders the sample's flythrough into build/out/flythrough/
#   tools/aerial.sh test   installs what is missing, builds, runs the whole test suite (CTest)
#   tools/aerial.sh sanitize  the clang ASan+UBSan build: the suite's subset and a short run of
#                          each fuzzer
#   tools/aerial.sh fuzz [SECONDS]  runs each libFuzzer target for SECONDS (default 300)
#   tools/aerial.sh regress [FLAGS...]  builds and runs aerial-regress (the software-GL regression
#                          runner; --bless re-blesses a device's goldens)
#
# Works from any directory. Needs Debian (apt) for the install step; root or sudo to install.
set -euo pipefail

# Debian packages. RUN_PACKAGES are what the sample game needs to build and render headless
# (xplanet: the star catalogue of its night);
# `test` adds TEST_PACKAGES (the tests, tools, the OpenSceneGraph adapter, the sanitizer build).
# Adding a dependency is adding one line to one of the lists.
RUN_PACKAGES=(
    build-essential
    cmake
    ninja-build
    pkg-config
    libglm-dev
    libhwy-dev
    libnova-dev
    nlohmann-json3-dev
    libcli11-dev
    libpng-dev
    libgl-dev
    libosmesa6-dev
    libegl-dev
    libegl-mesa0
    libopenmesh-dev
    libglfw3-dev
    xplanet
)
TEST_PACKAGES=(
    libgtest-dev
    liblcms2-dev
    libopenscenegraph-dev
    libirrlicht-dev
    xvfb
    xauth
    python3-matplotlib
    mesa-vulkan-drivers
    python3
    clang
    libclang-rt-14-dev
)
PACKAGES=("${RUN_PACKAGES[@]}" "${TEST_PACKAGES[@]}")
# What `run` builds: the sample game and nothing else (the tests and tools come with `test`).
RUN_TARGETS=(aerial-sample)

BUILD_DIR=build
# The clang build with AddressSanitizer, UndefinedBehaviorSanitizer and the libFuzzer targets.
SANITIZE_DIR=build-sanitize
# What `sanitize` runs there: the suite but these (CTest -E): the GL tests on softpipe, on EGL and
# with extensions hidden run the module's same code as on OSMesa llvmpipe (GL 1.3 and 1.1 stay:
# they take the combiner and two-pass paths), and the golden images render through aerial-render
# as test_aerial_render does; consumer.install_and_build links the installed (sanitized) static
# libraries into a program built without the sanitizer runtime, which cannot link (the Release
# suite checks the install). Plus each fuzzer for FUZZ_SMOKE_SECONDS.
SANITIZE_EXCLUDE='\.(softpipe|no_ext)$|\.egl\.|^regress\.|^consumer\.install_and_build$'
FUZZ_SMOKE_SECONDS=20
# What `test` runs in $SANITIZE_DIR/ after the Release suite (CI's budget does not hold the whole
# sanitizer build): the test executables of the core, the C interface, the mesh and the ARB
# program generator and interpreter, the OFF reader (no GL driver in the process), and every fuzzer
# for FUZZ_SMOKE_SECONDS. `sanitize` runs more. Nothing is excluded (CTest -E) at present.
SANITIZE_CI_EXCLUDE='^$'
SANITIZE_CI_TESTS=(test_core_accuracy test_core_atmosphere test_core_batch test_core_batch_kernels
    test_core_batch_rgba8 test_core_cache test_core_models test_core_phase test_core_sky
    test_core_stability test_core_sun test_core_night test_capi_c test_mesh test_mesh_bad_data
    test_gl_arb_program test_off_reader)
# The part of their longest seeded sweeps those tests run there (AERIAL_TEST_SCALE, see
# tests/test_scale.hpp): every operation costs about ten times more under the sanitizers. The
# stability sweeps and the longest ARB program grids print how many cases they kept; `sanitize`
# runs them whole.
SANITIZE_CI_SCALE=0.05
OUT_DIR="$BUILD_DIR/out"

usage() {
    cat <<EOF
Usage: tools/aerial.sh COMMAND [ARGS...]

Commands:
  run [FLAGS...]  install the missing packages of RUN_PACKAGES, configure a Release build in
                  $BUILD_DIR/ (CMake + Ninja) and build only ${RUN_TARGETS[*]}, then render
                  the sample's headless flythrough
                  (noon into a moonlit night, a ground-fog segment):
                  $BUILD_DIR/bin/aerial-sample --headless --frames 24 --out $OUT_DIR/flythrough
                  which writes frame_NNNN.png, contact_sheet.png and frames.csv there.
                  FLAGS are passed on to aerial-sample (for example --preset hazy --backend arb
                  --frames 48; see $BUILD_DIR/bin/aerial-sample --help).
  test            install every package, configure $BUILD_DIR/ with the tools and tests and
                  build everything, then run the whole suite:
                  ctest --test-dir $BUILD_DIR --output-on-failure -j2
                  then the sanitizer stage: configure $SANITIZE_DIR/ as for sanitize, build
                  the test executables of the core, the C interface, the mesh and the ARB
                  program (SANITIZE_CI_TESTS in this script) and the fuzzers, run those tests
                  (ctest -L) with AERIAL_TEST_SCALE=$SANITIZE_CI_SCALE (the longest seeded sweeps
                  in part) and each fuzzer for $FUZZ_SMOKE_SECONDS s
  sanitize        install, then configure $SANITIZE_DIR/ with clang,
                  -DAERIAL_SANITIZE=ON -DAERIAL_FUZZ=ON (AddressSanitizer with LeakSanitizer,
                  UndefinedBehaviorSanitizer, every finding fatal), builds it and runs
                  ctest --test-dir $SANITIZE_DIR -E '$SANITIZE_EXCLUDE' -j2
                  which is the suite without the softpipe, EGL and hidden-extension GL runs and
                  the golden images, plus every libFuzzer target of tests/fuzz for
                  $FUZZ_SMOKE_SECONDS s from its seed corpus (CTest label fuzz).
  fuzz [SECONDS]  install, configure and build $SANITIZE_DIR/ as above, then run every libFuzzer
                  target for SECONDS (default 300) and print the executions of each; new inputs
                  land in $SANITIZE_DIR/tests/fuzz/NAME/corpus, crashes next to it (crash-*).
  regress [FLAGS...]
                  install every package, configure $BUILD_DIR/ as for test, build aerial-regress
                  and run it with --out $BUILD_DIR/regress and FLAGS, for example
                  --gl egl --driver softpipe --tier portable, or --gl osmesa --driver llvmpipe
                  --bless to re-bless that device's goldens in tests/golden/osmesa-llvmpipe/
                  (review the images before committing them); see docs/regression-testing.md
  -h, --help      print this help

Packages installed when missing (apt-get, needs root or sudo):
  ${PACKAGES[*]}
EOF
}

say() { printf 'aerial.sh: %s\n' "$*"; }
die() {
    printf 'aerial.sh: error: %s\n' "$*" >&2
    exit 1
}

# Runs a command as root: directly when we are root, through sudo otherwise.
as_root() {
    if [[ $(id -u) -eq 0 ]]; then
        "$@"
    elif command -v sudo >/dev/null 2>&1; then
        sudo "$@"
    else
        die "not root and sudo is not available; run as root: $*"
    fi
}

is_installed() {
    local status
    status=$(dpkg-query -W -f='${Status}' "$1" 2>/dev/null) || return 1
    [[ $status == *"ok installed"* ]]
}

# Installs those of the packages given as arguments (default: PACKAGES) that are missing.
install_missing_packages() {
    local wanted=("$@")
    ((${#wanted[@]} > 0)) || wanted=("${PACKAGES[@]}")
    if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
        say "no dpkg/apt-get here: make sure these are installed: ${wanted[*]}"
        return
    fi
    local missing=() package
    for package in "${wanted[@]}"; do
        is_installed "$package" || missing+=("$package")
    done
    if ((${#missing[@]} == 0)); then
        say "all ${#wanted[@]} required packages are installed"
        return
    fi
    say "installing missing packages: ${missing[*]}"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get update ||
        die "apt-get update failed (see above)"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
        "${missing[@]}" || die "apt-get install failed for: ${missing[*]}"
}

# Configures $BUILD_DIR/ (Release, Ninja). With "sample" a new build directory leaves out the
# tools and tests (what `run` needs); with "all" they are switched on, in a new directory or in
# one that `run` configured without them.
configure() {
    local scope=$1 cache="$BUILD_DIR/CMakeCache.txt" generator=""
    if [[ -f $cache ]]; then
        generator=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$cache")
        if [[ -n $generator && $generator != Ninja ]]; then
            die "$BUILD_DIR/ was configured with the '$generator' generator, not Ninja; remove $BUILD_DIR/ and run again"
        fi
    fi
    local options=(-DAERIAL_BUILD_SAMPLE_GAME=ON -DAERIAL_BUILD_TOOLS=ON -DAERIAL_BUILD_TESTS=ON)
    if [[ -f $BUILD_DIR/build.ninja ]] &&
        grep -qx 'CMAKE_BUILD_TYPE:STRING=Release' "$cache" 2>/dev/null; then
        # Configured; Ninja re-runs CMake by itself when a CMakeLists.txt changes.
        if [[ $scope == sample ]] || { grep -qx 'AERIAL_BUILD_TESTS:BOOL=ON' "$cache" &&
            grep -qx 'AERIAL_BUILD_TOOLS:BOOL=ON' "$cache"; }; then
            return
        fi
        say "switching the tools and tests on in $BUILD_DIR/"
    elif [[ $scope == sample ]]; then
        options=(-DAERIAL_BUILD_SAMPLE_GAME=ON -DAERIAL_BUILD_TOOLS=OFF -DAERIAL_BUILD_TESTS=OFF)
        say "configuring a Release build of the sample game in $BUILD_DIR/"
    else
        say "configuring a Release build in $BUILD_DIR/"
    fi
    cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "${options[@]}"
}

# Builds, in the build directory given first, the targets given after it, or everything.
build_in() {
    local dir=$1 jobs
    shift
    jobs=$(nproc 2>/dev/null || echo 2)
    say "building $dir/ with $jobs jobs${1:+ (targets: $*)}"
    cmake --build "$dir" -j "$jobs" ${1:+--target "$@"}
}
build() { build_in "$BUILD_DIR" "$@"; }

configure_sanitize() {
    if [[ -f $SANITIZE_DIR/build.ninja ]] &&
        grep -qx 'AERIAL_FUZZ:BOOL=ON' "$SANITIZE_DIR/CMakeCache.txt" 2>/dev/null; then
        return
    fi
    command -v clang++ >/dev/null 2>&1 || die "clang++ not found (Debian packages clang, libclang-rt-14-dev)"
    say "configuring the sanitizer and fuzzing build in $SANITIZE_DIR/ (clang)"
    cmake -S . -B "$SANITIZE_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DAERIAL_FUZZ=ON \
        -DAERIAL_BUILD_SAMPLE_GAME=OFF
}

build_sanitize() { build_in "$SANITIZE_DIR" "$@"; }

fuzz_targets() {
    local dir
    for dir in tests/fuzz/corpus/*/; do
        basename "$dir"
    done
}

# Runs the fuzz tests (CTest label "fuzz") for $1 seconds each and prints libFuzzer's counts.
run_fuzzers() {
    local seconds=$1 status=0 name
    say "running each fuzzer for $seconds s"
    AERIAL_FUZZ_SECONDS=$seconds ctest --test-dir "$SANITIZE_DIR" -L '^fuzz$' -j2 \
        --output-on-failure --timeout $((seconds + 600)) || status=$?
    for name in $(fuzz_targets); do
        cat "$SANITIZE_DIR/tests/fuzz/$name/summary.txt" 2>/dev/null || true
    done
    return "$status"
}

main() {
    local command=${1:-}
    case $command in
        -h | --help | help)
            usage
            return 0
            ;;
        run | test | regress | sanitize | fuzz) shift ;;
        "")
            usage >&2
            printf '\naerial.sh: missing command (run, test, regress, sanitize or fuzz)\n' >&2
            exit 2
            ;;
        *)
            printf 'aerial.sh: unknown command %q (expected run, test, regress, sanitize or fuzz; see --help)\n' \
                "$command" >&2
            exit 2
            ;;
    esac
    local fuzz_seconds=300
    if [[ $command == fuzz && $# -gt 0 ]]; then
        if [[ ! $1 =~ ^[0-9]+$ || $1 -lt 1 || $1 -gt 604800 ]]; then
            printf 'aerial.sh: fuzz SECONDS: expected a whole number 1 .. 604800, got %q\n' "$1" >&2
            exit 2
        fi
        fuzz_seconds=$1
        shift
    fi
    if [[ $command != run && $command != regress && $# -gt 0 ]]; then
        printf 'aerial.sh: %s takes no further arguments, got %q (see --help)\n' "$command" "$1" >&2
        exit 2
    fi

    # Everything below runs from the repository root, whatever the caller's directory.
    cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.."

    if [[ $command == regress ]]; then
        install_missing_packages
        configure all
        say "building aerial-regress"
        cmake --build "$BUILD_DIR" --target aerial-regress
        "$BUILD_DIR/bin/aerial-regress" --out "$BUILD_DIR/regress" "$@"
        return
    fi
    if [[ $command == sanitize ]]; then
        install_missing_packages
        configure_sanitize
        build_sanitize
        say "running the sanitizer subset and the fuzz smoke ($FUZZ_SMOKE_SECONDS s per fuzzer)"
        AERIAL_FUZZ_SECONDS=$FUZZ_SMOKE_SECONDS \
            ctest --test-dir "$SANITIZE_DIR" -E "$SANITIZE_EXCLUDE" --output-on-failure -j2
        return
    fi
    if [[ $command == fuzz ]]; then
        install_missing_packages
        configure_sanitize
        # shellcheck disable=SC2046
        build_sanitize $(fuzz_targets)
        run_fuzzers "$fuzz_seconds"
        return
    fi
    if [[ $command == run ]]; then
        install_missing_packages "${RUN_PACKAGES[@]}"
        configure sample
        build "${RUN_TARGETS[@]}"
        mkdir -p "$OUT_DIR"
        say "rendering the sample's flythrough into $OUT_DIR/flythrough/"
        "$BUILD_DIR/bin/aerial-sample" --headless --frames 24 --out "$OUT_DIR/flythrough" "$@"
        say "pictures: $OUT_DIR/flythrough/contact_sheet.png and $OUT_DIR/flythrough/frame_*.png"
    else
        install_missing_packages
        configure all
        build
        # The tables of the light scattered more than once stay in the per-user cache for the
        # whole run (docs/models.md, "Table cache"): the sanitizer stage reads what the Release
        # suite computed instead of computing it again under AddressSanitizer (several times
        # slower). Left as the caller set it, if they did.
        export AERIAL_CACHE_MAX_MB=${AERIAL_CACHE_MAX_MB:-4096}
        say "running the test suite"
        ctest --test-dir "$BUILD_DIR" --output-on-failure -j2
        say "sanitizer stage: ${SANITIZE_CI_TESTS[*]} and the fuzzers under ASan+UBSan"
        configure_sanitize
        # shellcheck disable=SC2046
        build_sanitize "${SANITIZE_CI_TESTS[@]}" $(fuzz_targets)
        local labels
        labels="^($(IFS='|'; echo "${SANITIZE_CI_TESTS[*]}")|fuzz)\$"
        # A fixed fuzzer seed: the smoke tries the same inputs in the same order on every run, as
        # far as its time reaches (a faster machine gets further); longer runs, with new seeds,
        # are `fuzz`.
        AERIAL_FUZZ_SECONDS=$FUZZ_SMOKE_SECONDS AERIAL_FUZZ_SEED=1 AERIAL_TEST_SCALE=$SANITIZE_CI_SCALE \
            ctest --test-dir "$SANITIZE_DIR" -L "$labels" -E "$SANITIZE_CI_EXCLUDE" \
            --output-on-failure -j2
        for name in $(fuzz_targets); do
            cat "$SANITIZE_DIR/tests/fuzz/$name/summary.txt" 2>/dev/null || true
        done
    fi
}

main "$@"
