#!/usr/bin/env bash
# Builds the portable bundle: a tarball holding the `tavis` program, the Python module, the
# configs and every shared library they load beyond glibc, found through RPATH $ORIGIN/../lib, so
# that it runs where none of the project's Debian libraries are installed (a cluster node).
# docs/bundle.md describes the layout and how it is checked (tools/bundle/check_bundle.sh).
#
#   tools/bundle/make_bundle.sh [--build-dir DIR] [--out DIR] [--no-build]
#
# Without --no-build it configures DIR (default build/; Release, tests and benchmarks off) if it
# is not configured yet and builds the targets `tavis` and `tavis_python`. Prints the tarball's
# path: OUT/tavis-<git describe>-linux-<arch>.tar.gz (OUT defaults to DIR/bundle).
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
build_dir=$source_dir/build
out_dir=
build=1
while [ $# -gt 0 ]; do
  case $1 in
    --build-dir) build_dir=$2; shift 2 ;;
    --out) out_dir=$2; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "make_bundle.sh: unknown argument '$1' (--build-dir DIR, --out DIR, --no-build)" >&2; exit 2 ;;
  esac
done
build_dir=$(realpath -m "$build_dir")
out_dir=$(realpath -m "${out_dir:-$build_dir/bundle}")
command -v patchelf >/dev/null || { echo "make_bundle.sh: needs patchelf (apt-get install patchelf, or .ci/install-deps bundle)" >&2; exit 1; }

if [ $build -eq 1 ]; then
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    mkdir -p "$build_dir"
    cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 \
          -DTAVIS_BUILD_TESTS=OFF -DTAVIS_BUILD_BENCHMARKS=OFF > "$build_dir/configure.log" 2>&1 ||
      { cat "$build_dir/configure.log"; exit 1; }
  fi
  targets=(tavis)
  grep -q '^TAVIS_BUILD_PYTHON:BOOL=ON' "$build_dir/CMakeCache.txt" && targets+=(tavis_python)
  cmake --build "$build_dir" -j"$(nproc)" --target "${targets[@]}"
fi
[ -x "$build_dir/tavis" ] || { echo "make_bundle.sh: no program $build_dir/tavis (build the target tavis first)" >&2; exit 1; }

version=$(git -C "$source_dir" describe --always --dirty 2>/dev/null || echo unknown)
name=tavis-$version-linux-$(uname -m)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
stage=$work/$name

# The program and its configs, as `cmake --install` lays them out (bin/, share/tavis/configs).
cmake --install "$build_dir" --prefix "$stage" > "$work/install.log" 2>&1 || { cat "$work/install.log"; exit 1; }
mkdir -p "$stage/lib"
objects=("$stage/bin/tavis")
# The Python module, if it was built: lib/python/tavis (PYTHONPATH=<bundle>/lib/python).
module=$(find "$build_dir/python/tavis" -maxdepth 1 -name '_tavis*.so' 2>/dev/null | head -n 1)
if [ -n "$module" ]; then
  mkdir -p "$stage/lib/python"
  cp -r "$build_dir/python/tavis" "$stage/lib/python/"
  find "$stage/lib/python" -name __pycache__ -prune -exec rm -rf {} +
  objects+=("$stage/lib/python/tavis/$(basename "$module")")
fi

# glibc's own libraries and the dynamic loader stay the host's: they must match each other and
# the kernel, and every Linux has them. Everything else is copied under its soname.
is_glibc() {
  case $1 in
    ld-linux*.so.*|libc.so.*|libm.so.*|libmvec.so.*|libpthread.so.*|libdl.so.*|librt.so.*|libresolv.so.*|\
    libutil.so.*|libanl.so.*|libBrokenLocale.so.*|libnss_*.so.*|libthread_db.so.*|linux-vdso.so.*) return 0 ;;
  esac
  return 1
}
for object in "${objects[@]}"; do
  if ldd "$object" | grep -q 'not found'; then
    echo "make_bundle.sh: $object has unresolved libraries:" >&2; ldd "$object" | grep 'not found' >&2; exit 1
  fi
  ldd "$object" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | while read -r soname path; do
    is_glibc "$soname" && continue
    [ -e "$stage/lib/$soname" ] || install -m 0755 "$(realpath "$path")" "$stage/lib/$soname"
  done
done
# Each object finds the bundle's libraries relative to itself; each library finds its own
# dependencies next to itself (RUNPATH is not inherited by a library's dependencies).
patchelf --set-rpath '$ORIGIN/../lib' "$stage/bin/tavis"
[ -n "$module" ] && patchelf --set-rpath '$ORIGIN/../..' "$stage/lib/python/tavis/$(basename "$module")"
for library in "$stage"/lib/*.so*; do
  patchelf --set-rpath '$ORIGIN' "$library"
done

# The newest glibc symbol version any bundled object needs: the oldest glibc the bundle runs on.
glibc_needed=$(find "$stage/bin" "$stage/lib" -type f \( -name 'tavis' -o -name '*.so*' \) -exec objdump -T {} + 2>/dev/null |
               grep -o 'GLIBC_[0-9][0-9.]*' | sort -u -V | tail -n 1)
cat > "$stage/BUNDLE.txt" <<INFO
tavis $version, built $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(. /etc/os-release && echo "$PRETTY_NAME") ($(uname -m))
Needs: Linux $(uname -m) with glibc >= ${glibc_needed#GLIBC_}; nothing else (the other libraries are in lib/).
Run:    $name/bin/tavis eval            (configs: share/tavis/configs, found from bin/)
Python: PYTHONPATH=$name/lib/python python3 -c "import tavis"
        (CPython $(/usr/bin/python3 -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null || echo '?') with NumPy; the module was built for that version only)
Docs:   docs/bundle.md in the source repository.
INFO
[ -n "$module" ] || sed -i '/^Python:/,+1d' "$stage/BUNDLE.txt"

mkdir -p "$out_dir"
tarball=$out_dir/$name.tar.gz
tar -C "$work" -czf "$tarball.partial" "$name"
mv "$tarball.partial" "$tarball"
echo "make_bundle.sh: $(ls "$stage/lib" | grep -c '\.so') libraries, needs glibc >= ${glibc_needed#GLIBC_}, $(du -h "$tarball" | cut -f1)" >&2
echo "$tarball"
