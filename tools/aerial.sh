#!/usr/bin/env bash
# aerial.sh — sets up, builds and runs the project: the two commands of the README's Quick start.
#
#   tools/aerial.sh run    installs what is missing, builds, renders the sample headless into build/out/
#   tools/aerial.sh test   installs what is missing, builds, runs the whole test suite (CTest)
#
# Works from any directory. Needs Debian (apt) for the install step; root or sudo to install.
set -euo pipefail

# Debian packages the build and the tests need. Adding a dependency is adding one line here.
PACKAGES=(
    build-essential
    cmake
    ninja-build
    pkg-config
    libglm-dev
    libhwy-dev
    nlohmann-json3-dev
    libcli11-dev
    libgtest-dev
    libpng-dev
    libgl-dev
    libosmesa6-dev
    libegl-dev
    libegl-mesa0
    liblcms2-dev
    python3
)

BUILD_DIR=build
OUT_DIR="$BUILD_DIR/out"

usage() {
    cat <<EOF
Usage: tools/aerial.sh COMMAND [ARGS...]

Commands:
  run [FLAGS...]  install missing Debian packages, configure and build a Release build in
                  $BUILD_DIR/ (CMake + Ninja), then render the sample headless:
                  $BUILD_DIR/bin/aerial-sample --out $OUT_DIR/sample.png --csv $OUT_DIR/sample.csv
                  FLAGS are passed on to aerial-sample (for example --model reference --size 320x180;
                  see $BUILD_DIR/bin/aerial-sample --help).
  test            install, configure and build as above, then run the whole suite:
                  ctest --test-dir $BUILD_DIR --output-on-failure -j2
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

install_missing_packages() {
    if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
        say "no dpkg/apt-get here: make sure these are installed: ${PACKAGES[*]}"
        return
    fi
    local missing=() package
    for package in "${PACKAGES[@]}"; do
        is_installed "$package" || missing+=("$package")
    done
    if ((${#missing[@]} == 0)); then
        say "all ${#PACKAGES[@]} required packages are installed"
        return
    fi
    say "installing missing packages: ${missing[*]}"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get update ||
        die "apt-get update failed (see above)"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
        "${missing[@]}" || die "apt-get install failed for: ${missing[*]}"
}

configure() {
    local cache="$BUILD_DIR/CMakeCache.txt" generator=""
    if [[ -f $cache ]]; then
        generator=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$cache")
        if [[ -n $generator && $generator != Ninja ]]; then
            die "$BUILD_DIR/ was configured with the '$generator' generator, not Ninja; remove $BUILD_DIR/ and run again"
        fi
    fi
    if [[ -f $BUILD_DIR/build.ninja ]] &&
        grep -qx 'CMAKE_BUILD_TYPE:STRING=Release' "$cache" 2>/dev/null; then
        return  # configured; Ninja re-runs CMake by itself when a CMakeLists.txt changes
    fi
    say "configuring a Release build in $BUILD_DIR/"
    cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
}

build() {
    local jobs
    jobs=$(nproc 2>/dev/null || echo 2)
    say "building with $jobs jobs"
    cmake --build "$BUILD_DIR" -j "$jobs"
}

setup() {
    install_missing_packages
    configure
    build
}

main() {
    local command=${1:-}
    case $command in
        -h | --help | help)
            usage
            return 0
            ;;
        run | test) shift ;;
        "")
            usage >&2
            printf '\naerial.sh: missing command (run or test)\n' >&2
            exit 2
            ;;
        *)
            printf 'aerial.sh: unknown command %q (expected run or test; see --help)\n' \
                "$command" >&2
            exit 2
            ;;
    esac
    if [[ $command == test && $# -gt 0 ]]; then
        printf 'aerial.sh: test takes no arguments, got %q (see --help)\n' "$1" >&2
        exit 2
    fi

    # Everything below runs from the repository root, whatever the caller's directory.
    cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.."

    setup
    if [[ $command == run ]]; then
        mkdir -p "$OUT_DIR"
        say "rendering the sample into $OUT_DIR/"
        "$BUILD_DIR/bin/aerial-sample" --out "$OUT_DIR/sample.png" --csv "$OUT_DIR/sample.csv" "$@"
    else
        say "running the test suite"
        ctest --test-dir "$BUILD_DIR" --output-on-failure -j2
    fi
}

main "$@"
