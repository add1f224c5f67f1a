#!/bin/bash
# The portable bundle, built from this build tree by tools/bundle/make_bundle.sh and checked by
# tools/bundle/check_bundle.sh unpacked elsewhere: every library it loads comes from the bundle
# or glibc, `tavis eval` runs from it and writes the same records as the build tree's program,
# and (with a Python) the module imports and renders.
#
# usage: bundle_test.sh BUILD_DIR SOURCE_DIR [PYTHON]     (needs patchelf: .ci/install-deps --tests)
set -euo pipefail
build_dir=$1
source_dir=$2
python=${3:-}
out=$(mktemp -d /tmp/tavis_bundle_test.XXXXXX)
trap 'rm -rf "$out"' EXIT
tarball=$("$source_dir/tools/bundle/make_bundle.sh" --no-build --build-dir "$build_dir" --out "$out")
[ -f "$tarball" ] || { echo "FAIL: make_bundle.sh printed '$tarball', not a tarball"; exit 1; }
# Nothing of the build tree may leak in: the tarball holds no path of it.
if tar -tzf "$tarball" | grep -q "$build_dir"; then echo "FAIL: the tarball holds paths of the build tree"; exit 1; fi
args=("$tarball" --episodes 4 --reference "$build_dir/tavis")
[ -z "$python" ] || args+=(--python "$python")
"$source_dir/tools/bundle/check_bundle.sh" "${args[@]}"
