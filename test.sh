#!/bin/sh
# All tests of the workspace (`cargo test-host`), after installing what they need on a fresh
# Debian machine with rustup:
# - the thumbv7em-none-eabihf target: the deadline test builds the real firmware ELF;
# - cmake and libclang-dev: the Cortex-M4 cycle model (crate alvs-cycles) builds unicorn-engine
#   from C and generates its bindings with bindgen.
# Arguments go to `cargo test` (e.g. ./test.sh --test budget -- --nocapture).
set -eu
cd "$(dirname "$0")"

rustup target add thumbv7em-none-eabihf >/dev/null 2>&1 ||
    { echo "test.sh: rustup target add thumbv7em-none-eabihf failed" >&2; exit 1; }

missing=""
command -v cmake >/dev/null 2>&1 || missing="cmake"
dpkg -s libclang-dev >/dev/null 2>&1 || missing="$missing libclang-dev"
if [ -n "$missing" ]; then
    echo "test.sh: installing$missing (apt)" >&2
    if [ "$(id -u)" = 0 ]; then
        apt-get update -qq && apt-get install -y -qq $missing >/dev/null
    elif command -v sudo >/dev/null 2>&1; then
        sudo apt-get update -qq && sudo apt-get install -y -qq $missing >/dev/null
    else
        echo "test.sh: please install$missing (Debian: apt-get install$missing)" >&2
        exit 1
    fi
fi

exec cargo test-host "$@"
