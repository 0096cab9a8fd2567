#!/bin/sh
# Runs every test program in BUILD/tests (test_* and ref_*), adds up their counts and prints
# the closing line "N passed, N failed, N skipped".  Exit status: 0 only if nothing failed.
build=${1:-build}
tp=0; tf=0; ts=0; bad=""
for t in "$build"/tests/test_* "$build"/tests/ref_*; do
    [ -x "$t" ] || continue
    case "$t" in *.d|*.o) continue ;; esac
    out=$("$t" 2>&1); rc=$?
    printf '%s\n' "$out" | grep -E '^(FAIL|SKIP)' | head -n 40
    line=$(printf '%s\n' "$out" | grep -E ': [0-9]+ passed, [0-9]+ failed, [0-9]+ skipped$' | tail -n 1)
    if [ -z "$line" ]; then
        echo "$(basename "$t"): crashed or printed no summary (exit $rc)"
        printf '%s\n' "$out" | tail -n 5
        tf=$((tf + 1)); bad="$bad $(basename "$t")"; continue
    fi
    echo "$line"
    p=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed, ([0-9]+) skipped$/\1/')
    f=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed, ([0-9]+) skipped$/\2/')
    s=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed, ([0-9]+) skipped$/\3/')
    tp=$((tp + p)); tf=$((tf + f)); ts=$((ts + s))
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then tf=$((tf + 1)); bad="$bad $(basename "$t")"; fi
    [ "$f" -ne 0 ] && bad="$bad $(basename "$t")"
done
[ -n "$bad" ] && echo "failing programs:$bad"
echo "$tp passed, $tf failed, $ts skipped"
[ "$tf" -eq 0 ]
