#!/usr/bin/env bash
# Builds the MuJoCo engine plugin `flapwing.wings`: target/release/libflapwing_mujoco.so.
#
# Usage: crates/mujoco/build.sh [PYTHON]   (FLAPWING_STATICLIB: a libflapwing.a to link)
#   PYTHON (default: $FLAPWING_PYTHON, else python3) is a Python with the `mujoco` package from
#   PyPI: the plugin is compiled against the headers (include/mujoco/*.h) and linked against the
#   libmujoco.so.* that this package ships. The flapwing C ABI (crates/ffi) is built with cargo
#   (`--release`, into $CARGO_TARGET_DIR or target/) and linked statically (libflapwing.a), so
#   the plugin is one self-contained shared library: it needs only libmujoco and the C library.
# Prints the plugin's path on stdout (diagnostics on stderr). CC overrides the compiler (gcc).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
py=${1:-${FLAPWING_PYTHON:-python3}}
cc=${CC:-gcc}
target_dir=${CARGO_TARGET_DIR:-$root/target}

mj=$("$py" -c 'import mujoco, os; print(os.path.dirname(mujoco.__file__))') || {
    echo "crates/mujoco/build.sh: \`$py\` cannot import mujoco (pip install mujoco)" >&2
    exit 1
}
libmujoco=$(cd "$mj" && ls libmujoco.so.* 2>/dev/null | head -n 1)
if [[ -z $libmujoco || ! -f $mj/include/mujoco/mjplugin.h ]]; then
    echo "crates/mujoco/build.sh: no libmujoco.so.* or include/mujoco/mjplugin.h in $mj" >&2
    exit 1
fi

# The C ABI as a static library: FLAPWING_STATICLIB if given (scripts/test passes the one
# `cargo test` built), else built with cargo (a no-op when it is current).
if [[ -n ${FLAPWING_STATICLIB:-} ]]; then
    staticlib=$FLAPWING_STATICLIB
else
    (cd "$root" && CARGO_TARGET_DIR="$target_dir" cargo build --release --quiet -p flapwing-ffi >&2)
    staticlib="$target_dir/release/libflapwing.a"
fi
header_dir="${FLAPWING_INCLUDE_DIR:-$root/crates/ffi/include}"
[[ -f $staticlib && -f $header_dir/flapwing.h ]] || {
    echo "crates/mujoco/build.sh: missing $staticlib or $header_dir/flapwing.h" >&2
    exit 1
}

out="$target_dir/release/libflapwing_mujoco.so"
# --exclude-libs,ALL keeps libflapwing.a's (Rust) symbols out of the plugin's dynamic symbol
# table, so they cannot clash with another Rust library in the host process (e.g. the flapwing
# Python package); --gc-sections drops what the plugin does not call. libmujoco is linked by
# its soname (as MuJoCo's own plugins are), found in the package directory (rpath) or, when the
# host has already loaded it, reused.
# -fexceptions: a failed `init` raises mju_error, which MuJoCo's compiler turns into a C++
# exception that unwinds through the plugin's C frames.
"$cc" -std=c11 -O2 -fPIC -fexceptions -shared -Wall -Wextra -Werror \
    -I"$mj/include" -I"$header_dir" \
    "$root/crates/mujoco/flapwing_mujoco.c" "$root/crates/mujoco/config.c" \
    "$staticlib" \
    -L"$mj" -l:"$libmujoco" -Wl,-rpath,"$mj" \
    -Wl,--exclude-libs,ALL -Wl,--gc-sections -Wl,--strip-debug -Wl,--no-undefined \
    -lpthread -ldl -lm -lgcc_s -lc \
    -o "$out"
echo "$out"
