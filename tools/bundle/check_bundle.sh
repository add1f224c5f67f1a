#!/usr/bin/env bash
# Checks a portable bundle (tools/bundle/make_bundle.sh) the way a cluster node would use it:
#
#   tools/bundle/check_bundle.sh TARBALL [--root ROOT] [--episodes N] [--reference TAVIS] [--python PY]
#
# It unpacks the tarball (into ROOT/opt with --root, else a temporary folder), then checks that
#  - every library the program and the Python module load resolves into the bundle's lib/, except
#    glibc's own (ldd, inside ROOT with --root);
#  - with --root: none of the project's libraries (ODE, Embree, TBB, yaml-cpp, OpenCV, FFmpeg,
#    Snappy) exists in ROOT (a root without the project's Debian packages: docs/bundle.md);
#  - `tavis eval` runs a cell (the default cell of 96 episodes unless --episodes N) from the
#    bundle, run inside ROOT with chroot (needs root), writing N records and summary.json;
#  - with --reference TAVIS: that program writes byte-identical episodes.jsonl for the same cell;
#  - with --python PY (a python inside ROOT with --root): the module imports and steps an env.
# Exits non-zero naming the first failed check.
set -euo pipefail
usage="usage: check_bundle.sh TARBALL [--root ROOT] [--episodes N] [--reference TAVIS] [--python PY]"
[ $# -ge 1 ] || { echo "$usage" >&2; exit 2; }
tarball=$(realpath "$1"); shift
root= episodes= reference= python=
while [ $# -gt 0 ]; do
  case $1 in
    --root) root=$(realpath "$2"); shift 2 ;;
    --episodes) episodes=$2; shift 2 ;;
    --reference) reference=$(realpath "$2"); shift 2 ;;
    --python) python=$2; shift 2 ;;
    *) echo "check_bundle.sh: unknown argument '$1'; $usage" >&2; exit 2 ;;
  esac
done
[ -f "$tarball" ] || { echo "check_bundle.sh: no tarball '$tarball'" >&2; exit 2; }
fail() { echo "check_bundle.sh: FAILED: $*" >&2; exit 1; }

mounted_proc=0
# inside: the bundle's parent as the checked program sees it; host: the same folder from here.
if [ -n "$root" ]; then
  [ "$(id -u)" -eq 0 ] || fail "--root needs root (chroot)"
  inside=/opt/tavis-bundle-check
  host=$root$inside
  rm -rf "$host"
  # The program finds its configs through /proc/self/exe, as on any node: the root needs /proc.
  if ! mountpoint -q "$root/proc"; then mount -t proc proc "$root/proc"; mounted_proc=1; fi
  run() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root "$@"; }
else
  host=$(mktemp -d)
  inside=$host
  run() { env -u LD_LIBRARY_PATH -u PYTHONPATH "$@"; }
fi
trap '[ -n "$root" ] || rm -rf "$host"; [ "$mounted_proc" -eq 0 ] || umount "$root/proc"' EXIT
mkdir -p "$host"
tar -C "$host" -xzf "$tarball"
name=$(ls "$host")
bundle=$inside/$name
echo "check_bundle.sh: unpacked $name into ${root:+$root:}$inside"

glibc_pattern='^(ld-linux[^ ]*|libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libanl)\.so'
check_resolved() {  # $1: an object inside the bundle
  local listing
  listing=$(run ldd "$1") || fail "ldd $1"
  if grep -q 'not found' <<<"$listing"; then fail "$1 has unresolved libraries: $(grep 'not found' <<<"$listing")"; fi
  local outside
  # ldd prints RUNPATH-found paths unnormalised (bin/../lib/, lib/python/tavis/../../).
  outside=$(awk '$2 == "=>" {print $1, $3}' <<<"$listing" | sed -e 's|/bin/\.\./lib/|/lib/|' -e 's|/lib/python/tavis/\.\./\.\./|/lib/|' |
            grep -Ev "$glibc_pattern" | grep -v " $bundle/lib/[^/]*$" || true)
  [ -z "$outside" ] || fail "$1 loads libraries from outside the bundle: $outside"
  echo "check_bundle.sh: $(basename "$1"): all $(grep -c '=>' <<<"$listing") libraries from the bundle or glibc"
}
check_resolved "$bundle/bin/tavis"
module=$(cd "$host/$name" && ls lib/python/tavis/_tavis*.so 2>/dev/null || true)
[ -z "$module" ] || check_resolved "$bundle/$module"

if [ -n "$root" ]; then
  # The project's own dependencies must be missing from ROOT; a base system may have a few
  # general ones (zstd, zlib), which ldd above showed are taken from the bundle all the same.
  project_libraries='^lib(ode|embree|tbb|yaml-cpp|opencv|avcodec|avformat|avutil|swscale|snappy)'
  present=() project_present=()
  needed=$(objdump -p "$host/$name/bin/tavis" | awk '$1 == "NEEDED" {print $2}')
  for library in $needed; do
    [[ $library =~ $glibc_pattern|^libstdc\+\+|^libgcc_s ]] && continue
    [ -n "$(find "$root/usr/lib" "$root/lib" "$root/usr/local/lib" -name "$library" 2>/dev/null | head -n 1)" ] || continue
    present+=("$library")
    [[ $library =~ $project_libraries ]] && project_present+=("$library")
  done
  [ ${#project_present[@]} -eq 0 ] || fail "$root already has ${project_present[*]}: not a root without the project's libraries"
  echo "check_bundle.sh: $root has none of the project's libraries; of the program's $(wc -w <<<"$needed") direct" \
       "libraries it has only ${present[*]:-none} (besides glibc, libstdc++, libgcc_s)"
fi

cell_args=(eval --quiet)
[ -z "$episodes" ] || cell_args+=(--episodes "$episodes")
run "$bundle/bin/tavis" "${cell_args[@]}" --out "$inside/cell" > "$host/eval.log" 2>&1 ||
  fail "tavis eval from the bundle: $(cat "$host/eval.log")"
[ -f "$host/cell/summary.json" ] || fail "no summary.json after tavis eval"
records=$(wc -l < "$host/cell/episodes.jsonl")
[ "$records" -eq "${episodes:-96}" ] || fail "episodes.jsonl has $records records, expected ${episodes:-96}"
echo "check_bundle.sh: tavis eval from the bundle: $records episodes; $(tail -n 1 "$host/eval.log")"

if [ -n "$reference" ]; then
  "$reference" "${cell_args[@]}" --out "$host/reference_cell" > "$host/reference.log" 2>&1 ||
    fail "the reference $reference: $(cat "$host/reference.log")"
  cmp -s "$host/cell/episodes.jsonl" "$host/reference_cell/episodes.jsonl" ||
    fail "episodes.jsonl differs from the reference program's"
  echo "check_bundle.sh: episodes.jsonl identical to $reference's"
fi

if [ -n "$python" ]; then
  [ -n "$module" ] || fail "--python given but the bundle has no Python module"
  run env PYTHONPATH="$bundle/lib/python" "$python" -c '
import numpy as np, tavis
env = tavis.make_vec("clutter-pick-cube", num_envs=2, seed=0, cameras=["head"], image_size=(64, 64))
obs, infos = env.reset(seed=0)
obs, rewards, terminated, truncated, infos = env.step(np.zeros((2, tavis.ACTION_SIZE), dtype=np.float32))
assert obs["pixels"]["OBS_HEAD"].shape == (2, 64, 64, 3), obs["pixels"]["OBS_HEAD"].shape
assert obs["pixels"]["OBS_HEAD"].any(), "the rendered head images are all black"
print("stepped", env.num_envs, "envs from", tavis.__file__)
' > "$host/python.log" 2>&1 || fail "the Python module from the bundle: $(cat "$host/python.log")"
  echo "check_bundle.sh: python: $(tail -n 1 "$host/python.log")"
fi
echo "check_bundle.sh: all checks passed"
