#!/bin/sh
# run_tests.sh — runs the test programs, several at a time, and adds up their counts.
#
#   sh tests/run_tests.sh [--full] [-j N] [--build DIR] [PROGRAM ...]
#
# Test programs are the executables DIR/tests/test_* and DIR/tests/ref_* (DIR: build), or the
# PROGRAMs named (test_cli, ...).  N run at a time (default: the number of CPUs), longest first
# (by the last run's time).  Each runs from the repository root with
#   Q2N_SCRATCH         DIR/scratch/<program>, emptied first: every file it writes goes there
#   Q2N_EXE             DIR/quad2nurbs unless set
#   Q2N_SHARED_MESHES   ../shared/meshes unless set
#   Q2N_TEST_FULL       1 with --full (make check-full): the long sweeps run too
#   Q2N_REQUIRE_SHARED  passed on (CI sets 1: a missing shared mesh fails)
# and a time limit of Q2N_TEST_TIMEOUT seconds (default 3600).  Its output goes to
# DIR/scratch/<program>.log; as each program ends, its FAIL, SKIP and DEFER lines and its summary
# are printed with its CPU and wall seconds.  The last line is "N passed, N failed, N skipped";
# the exit status is 0 only if nothing failed.
set -u
cd "$(dirname "$0")/.." || exit 2

# ---- one program (run by the parallel workers below) --------------------------------------
if [ "${1:-}" = "--one" ]; then
    prog=$2 build=$3
    name=$(basename "$prog")
    dir=$build/scratch/$name log=$build/scratch/$name.log st=$build/scratch/.run/$name
    rm -rf "$dir" "$st.result" && mkdir -p "$dir" "$build/scratch/.run" || exit 2
    t0=$(date +%s.%N)
    (
        Q2N_SCRATCH=$dir timeout "${Q2N_TEST_TIMEOUT:-3600}" "$prog" > "$log" 2>&1
        echo $? > "$st.rc"
        times > "$st.times"       # second line: CPU time of the program and its children
    )
    t1=$(date +%s.%N)
    rc=$(cat "$st.rc")
    cpu=$(sed -n 2p "$st.times" | awk '{ s = 0; for (i = 1; i <= 2; i++) { split($i, a, /[ms]/); s += 60 * a[1] + a[2] }
                                          printf "%.1f", s }')
    wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
    echo "$wall $cpu" > "$st.time"
    line=$(grep -E ': [0-9]+ passed, [0-9]+ failed, [0-9]+ skipped$' "$log" | tail -n 1)
    out=$(grep -E '^(FAIL|SKIP|DEFER)' "$log" | head -n 40)
    if [ -z "$line" ]; then
        if [ "$rc" -eq 124 ]; then why="timed out after ${Q2N_TEST_TIMEOUT:-3600} s"
        else why="crashed or printed no summary (exit $rc)"; fi
        out="$out${out:+
}$name: $why; last lines of $log:
$(tail -n 5 "$log")"
        line="$name: 0 passed, 1 failed, 0 skipped"
    elif [ "$rc" -ne 0 ] && echo "$line" | grep -q ' 0 failed,'; then
        out="$out${out:+
}$name: exit status $rc although no check failed"
        line=$(echo "$line" | sed -E 's/ 0 failed,/ 1 failed,/')
    fi
    echo "$line" > "$st.result"
    printf '%s%s%-64s cpu %6.1f s  wall %6.1f s\n' "$out" "${out:+
}" "$line" "$cpu" "$wall"
    exit 0
fi

# ---- options --------------------------------------------------------------------------------
full=0 jobs="" build=build progs=""
while [ $# -gt 0 ]; do
    case "$1" in
    --full) full=1 ;;
    -j) jobs=$2; shift ;;
    -j*) jobs=${1#-j} ;;
    --build) build=$2; shift ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    -*) echo "run_tests.sh: unknown option $1" >&2; exit 2 ;;
    *) progs="$progs $1" ;;
    esac
    shift
done
[ -n "$jobs" ] || jobs=$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)

export Q2N_EXE="${Q2N_EXE:-$build/quad2nurbs}"
export Q2N_SHARED_MESHES="${Q2N_SHARED_MESHES:-../shared/meshes}"
export Q2N_REQUIRE_SHARED="${Q2N_REQUIRE_SHARED:-0}"
if [ "$full" -eq 1 ]; then export Q2N_TEST_FULL=1; else export Q2N_TEST_FULL=0; fi

if [ -z "$progs" ]; then
    for t in "$build"/tests/test_* "$build"/tests/ref_*; do
        case "$t" in *.d|*.o) continue ;; esac
        [ -f "$t" ] && [ -x "$t" ] && progs="$progs $t"
    done
else
    list=""
    for p in $progs; do
        t=$build/tests/$(basename "$p")
        [ -x "$t" ] || { echo "run_tests.sh: no test program $t (make check builds them)" >&2; exit 2; }
        list="$list $t"
    done
    progs=$list
fi
[ -n "$progs" ] || { echo "run_tests.sh: no test programs in $build/tests (make check builds them)"; exit 1; }

if [ ! -d "$Q2N_SHARED_MESHES" ]; then
    if [ "$Q2N_REQUIRE_SHARED" != 0 ]; then
        echo "shared test meshes: $Q2N_SHARED_MESHES does not exist and Q2N_REQUIRE_SHARED=1: their cases fail"
    else
        echo "shared test meshes: $Q2N_SHARED_MESHES does not exist: their cases are skipped"
    fi
fi
mode=quick
[ "$full" -eq 1 ] && mode=full
echo "running $(echo "$progs" | wc -w | tr -d ' ') test programs, $jobs at a time ($mode mode, logs in $build/scratch/)"

# ---- run, longest first (last run's wall time; programs never timed first) -------------------
mkdir -p "$build/scratch"
start=$(date +%s.%N)
for t in $progs; do
    w=$(cut -d' ' -f1 "$build/scratch/.run/$(basename "$t").time" 2>/dev/null || echo 1e9)
    echo "${w:-1e9} $t"
done | sort -g -r | awk '{ print $2 }' | xargs -P "$jobs" -I '{}' sh tests/run_tests.sh --one '{}' "$build"

# ---- totals --------------------------------------------------------------------------------
tp=0 tf=0 ts=0 bad="" defer=0
for t in $progs; do
    name=$(basename "$t")
    r=$(cat "$build/scratch/.run/$name.result" 2>/dev/null || echo "$name: 0 passed, 1 failed, 0 skipped")
    set -- $(echo "$r" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed, ([0-9]+) skipped$/\1 \2 \3/')
    tp=$((tp + $1)) tf=$((tf + $2)) ts=$((ts + $3))
    [ "$2" -ne 0 ] && bad="$bad $name"
    d=$(grep -c '^DEFER' "$build/scratch/$name.log" 2>/dev/null) || d=0
    defer=$((defer + d))
done
[ -n "$bad" ] && echo "failing programs:$bad"
[ "$defer" -gt 0 ] && echo "$defer long sweeps left out (DEFER lines): make check-full runs them"
awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "wall time %.0f s\n", b - a }'
echo "$tp passed, $tf failed, $ts skipped"
[ "$tf" -eq 0 ]
