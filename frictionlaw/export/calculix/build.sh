#!/usr/bin/env bash
# Build CalculiX's ccx 2.20 from Debian's calculix-ccx source package, with the user-friction
# patch beside this script and a FRIC-compatible friction routine linked in.
#
#   bash build.sh [--jobs N] [--work DIR] [--routine FILE] [--out FILE] [--lib-only]
#
# Defaults (paths relative to this script's folder):
#   --jobs     the number of CPUs (nproc)
#   --work     $SBMF_CCX_WORK if set, else ${XDG_CACHE_HOME:-~/.cache}/sbmf-friction/ccx-2.20
#              (the source, the objects, the patched library: outside the export folder, kept
#              and shared by every export; rebuilt when the patch differs)
#   --routine  sbmf_fric.f        (the routine written by frictionlaw-export calculix)
#   --out      ccx                (the binary; frictionlaw-export --force replaces it with the
#              rest of the export)
#   --lib-only build the patched library (and the unpatched reference binary) and stop
# Needs: a deb-src entry for Debian's sources, dpkg-dev (apt-get source), gfortran, gcc, make,
# patch, and the build dependencies libspooles-dev, libarpack2-dev, liblapack-dev
# (`apt-get build-dep calculix-ccx` installs them). Also writes WORK/ccx_reference, the same
# source built without the patch, for comparisons. Prints the binary's path on stdout.
# Exit status: 0 built, 1 the build failed, 2 something it needs is missing or bad options.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
jobs="$(nproc 2>/dev/null || echo 1)"
work="${SBMF_CCX_WORK:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/sbmf-friction/ccx-2.20}"
routine="$here/sbmf_fric.f"
out="$here/ccx"
lib_only=0
patchfile="$here/calculix-2.20-user-friction.patch"
version="2.20"

die() { echo "build.sh: error: $1" >&2; exit "${2:-1}"; }
while [ $# -gt 0 ]; do
    case "$1" in
        --jobs) [ $# -ge 2 ] || die "--jobs needs a value" 2; jobs="$2"; shift 2 ;;
        --work) [ $# -ge 2 ] || die "--work needs a value" 2; work="$2"; shift 2 ;;
        --routine) [ $# -ge 2 ] || die "--routine needs a value" 2; routine="$2"; shift 2 ;;
        --out) [ $# -ge 2 ] || die "--out needs a value" 2; out="$2"; shift 2 ;;
        --lib-only) lib_only=1; shift ;;
        -h|--help) sed -n '2,20p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) die "unknown option $1 (see --help)" 2 ;;
    esac
done
case "$jobs" in ''|*[!0-9]*|0) die "--jobs must be an integer >= 1, got '$jobs'" 2 ;; esac
[ -f "$patchfile" ] || die "the patch $patchfile is missing" 2
if [ "$lib_only" -eq 0 ] && [ ! -f "$routine" ]; then
    die "the friction routine $routine is missing (--routine)" 2
fi

# What the build needs, checked before any work; every missing piece is named.
missing=()
for tool in gfortran gcc make patch apt-get dpkg-source ar; do
    command -v "$tool" >/dev/null 2>&1 || missing+=("$tool")
done
[ -f /usr/include/spooles/SPOOLES.h ] || missing+=("libspooles-dev (SPOOLES headers)")
have_lib() { ldconfig -p 2>/dev/null | grep -q "lib$1\.so " || ls /usr/lib/*/lib"$1".so >/dev/null 2>&1; }
have_lib arpack || missing+=("libarpack2-dev")
have_lib lapack || missing+=("liblapack-dev")
have_lib blas || missing+=("libblas-dev")
if [ "${#missing[@]}" -gt 0 ]; then
    {
        echo "build.sh: missing: ${missing[*]}"
        echo "  Debian/Ubuntu, as root: apt-get install -y gfortran gcc make patch dpkg-dev \\"
        echo "      libspooles-dev libarpack2-dev liblapack-dev libblas-dev"
        echo "  (or: apt-get build-dep calculix-ccx)"
    } >&2
    exit 2
fi

cflags="-Wall -O2 -I/usr/include/spooles -DARCH=\"Linux\" -DSPOOLES -DARPACK -DMATRIXSTORAGE -DUSE_MT=1"
fflags="-O2 -fallow-argument-mismatch"
libs="-lspooles -lpthread -larpack -llapack -lblas -lm -lc -fopenmp"
patch_sum="$(sha256sum "$patchfile" | cut -c1-64)"
mkdir -p "$work" || die "cannot create the build folder $work (--work)" 2
work="$(cd "$work" && pwd)"
src="$work/calculix-ccx-$version/ccx_$version/src"
stamp="$work/patched.sha256"
# one build at a time in a shared build folder (flock, where util-linux has it)
if command -v flock >/dev/null 2>&1; then
    exec 9>"$work/.lock"
    flock 9
fi

if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$patch_sum" ] || [ ! -f "$src/ccx_$version.a" ]; then
    # the source: Debian's calculix-ccx 2.20 (Debian's own patches applied by apt-get source)
    rm -rf "$work/calculix-ccx-$version" "$stamp"
    # (|| true: awk stops reading at the first match, and under pipefail a SIGPIPE of
    # apt-cache must not end the script)
    debver="$(apt-cache showsrc calculix-ccx 2>/dev/null | awk -v v="$version" \
        '$1 == "Version:" && index($2, v "-") == 1 {print $2; exit}' || true)"
    if [ -z "$debver" ]; then
        {
            echo "build.sh: apt knows no source package calculix-ccx $version."
            echo "  apt-get source needs a deb-src entry: in /etc/apt/sources.list.d/debian.sources"
            echo "  write 'Types: deb deb-src' (or add a 'deb-src' line to /etc/apt/sources.list),"
            echo "  then run apt-get update. The patch is for CalculiX $version (Debian 12)."
        } >&2
        exit 2
    fi
    echo "build.sh: fetching the calculix-ccx $version source" >&2
    (cd "$work" && apt-get source -qq "calculix-ccx=$debver" >&2) ||
        die "apt-get source calculix-ccx failed"
    [ -d "$src" ] || die "no $src after apt-get source"
    echo "build.sh: compiling CalculiX $version with $jobs jobs (a few minutes)" >&2
    make -C "$src" -j "$jobs" CFLAGS="$cflags" FFLAGS="$fflags" "ccx_$version.a" "ccx_$version.o" \
        >"$work/build-reference.log" 2>&1 || die "the build failed: see $work/build-reference.log"
    gfortran -O2 -o "$work/ccx_reference" "$src/ccx_$version.o" "$src/ccx_$version.a" $libs ||
        die "linking the reference ccx failed"
    echo "build.sh: applying the user-friction patch" >&2
    (cd "$work/calculix-ccx-$version" && patch -p1 --forward --quiet <"$patchfile") ||
        die "the patch does not apply to this source"
    make -C "$src" -j "$jobs" CFLAGS="$cflags" FFLAGS="$fflags" "ccx_$version.a" "ccx_$version.o" \
        >"$work/build-patched.log" 2>&1 || die "the patched build failed: see $work/build-patched.log"
    printf '      IMPLICIT REAL*8(A-H,O-Z)\n      PARAMETER (NPRECD=2)\n' >"$work/ABA_PARAM.INC"
    echo "$patch_sum" >"$stamp"
fi
if [ "$lib_only" -eq 1 ]; then
    echo "$work"
    exit 0
fi

# the routine, compiled with Abaqus' ABA_PARAM.INC convention (implicit double precision) and
# -fopenmp: ccx calls it from several threads, and its guards' once-per-process flag is set
# with OpenMP atomics (the link below already takes libgomp)
obj="$work/user_fric.$$.o"
gfortran -O2 -fopenmp -I"$work" -c "$routine" -o "$obj" ||
    { rm -f "$obj"; die "compiling $routine failed"; }
tmp="$out.tmp.$$"
gfortran -O2 -o "$tmp" "$src/ccx_$version.o" "$obj" "$src/ccx_$version.a" $libs ||
    { rm -f "$tmp" "$obj"; die "linking ccx failed"; }
rm -f "$obj"
mv -f "$tmp" "$out"
echo "$(cd "$(dirname "$out")" && pwd)/$(basename "$out")"
