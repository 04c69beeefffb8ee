#!/usr/bin/env bash
# Builds the FMU flapwing_wings.fmu (FMI 2.0 co-simulation, linux64) with gcc and zip.
#
# Usage: crates/fmu/build.sh [OUT_DIR]          (default OUT_DIR: crates/fmu/build)
# Environment:
#   FLAPWING_STATICLIB  the C ABI's staticlib (crates/ffi), default
#                       ${CARGO_TARGET_DIR:-<repo>/target}/release/libflapwing.a
#                       (build it with `cargo build --release -p flapwing-ffi`)
#   FLAPWING_INCLUDE    directory of flapwing.h, default <repo>/crates/ffi/include
#   FMI2_HEADERS        directory of the FMI 2.0 headers (fmi2Functions.h ...), default the
#                       copy fmpy ships (fmpy/c-code), found with ${PYTHON:-python3}
#   CC                  default gcc
# Output: OUT_DIR/flapwing_wings.fmu, its unpacked tree OUT_DIR/fmu/, OUT_DIR/gen (the
# modelDescription.xml generator) and OUT_DIR/reference (the C ABI stepped without FMI, for
# the tests; see reference.c). The .so holds libflapwing.a; it exports the fmi2* functions
# only.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
out="$(mkdir -p "${1:-$here/build}" && cd "${1:-$here/build}" && pwd)"
cc="${CC:-gcc}"
staticlib="${FLAPWING_STATICLIB:-${CARGO_TARGET_DIR:-$repo/target}/release/libflapwing.a}"
include="${FLAPWING_INCLUDE:-$repo/crates/ffi/include}"
fmi2="${FMI2_HEADERS:-}"
if [ -z "$fmi2" ]; then
  fmi2="$("${PYTHON:-python3}" -c 'import fmpy, os; print(os.path.join(os.path.dirname(fmpy.__file__), "c-code"))')" ||
    { echo "build.sh: FMI2_HEADERS is unset and fmpy is not importable by ${PYTHON:-python3}" >&2; exit 2; }
fi
for f in "$staticlib" "$include/flapwing.h" "$fmi2/fmi2Functions.h"; do
  [ -f "$f" ] || { echo "build.sh: missing $f (see the environment variables at the top of $0)" >&2; exit 2; }
done
version="$(sed -n 's/^version = "\(.*\)"/\1/p' "$repo/Cargo.toml" | head -n1)"

# modelDescription.xml from the variable table (flapwing_fmu_vars.h).
"$cc" -std=c11 -O1 -Wall -Wextra -Werror "$here/gen_model_description.c" -o "$out/gen" -lm
rm -rf "$out/fmu" "$out/flapwing_wings.fmu"
mkdir -p "$out/fmu/binaries/linux64"
"$out/gen" "$version" > "$out/fmu/modelDescription.xml"

# The shared library: our fmi2* functions exported, every symbol of libflapwing.a hidden
# (--exclude-libs) so that a host loading other Rust libraries sees no clash; --no-undefined
# makes a missing C ABI function a link error here, not a load error in the host.
"$cc" -std=c11 -O2 -g -Wall -Wextra -Werror -fPIC -fvisibility=hidden -shared \
  -I"$fmi2" -I"$include" "$here/flapwing_fmu.c" "$staticlib" \
  -Wl,--exclude-libs,ALL -Wl,--gc-sections -Wl,--no-undefined \
  -lpthread -ldl -lm -lrt \
  -o "$out/fmu/binaries/linux64/flapwing_wings.so"

# The C ABI's own numbers, stepped as fmi2DoStep steps (for tests/python/test_fmu.py).
"$cc" -std=c11 -O2 -Wall -Wextra -Werror -I"$include" "$here/reference.c" "$staticlib" \
  -lpthread -ldl -lm -lrt -o "$out/reference"

(cd "$out/fmu" && zip -q -r -X "$out/flapwing_wings.fmu" modelDescription.xml binaries)
echo "$out/flapwing_wings.fmu"
