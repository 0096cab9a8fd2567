#!/bin/sh
# Runs every benchmark program in BUILD/bench (not tests: they print figures, they assert nothing).
build=${1:-build}
for b in "$build"/bench/*; do
    [ -x "$b" ] || continue
    case "$b" in *.d|*.o) continue ;; esac
    "$b"
done
