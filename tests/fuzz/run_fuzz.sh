#!/bin/sh
# run_fuzz.sh FUZZ_DIR SECONDS — bounded libFuzzer run of each harness (`make fuzz-check`):
# seeds from make_corpus.sh, a corpus that grows across runs in FUZZ_DIR/corpus_*, crash inputs in
# FUZZ_DIR/artifacts/.  Prints executions and findings per harness; exit status 1 when a harness
# found a crash, a leak, a sanitizer report, a timeout or a violated invariant.
dir=${1:?usage: run_fuzz.sh FUZZ_DIR [SECONDS]}
secs=${2:-60}
here=$(dirname "$0")
sh "$here/make_corpus.sh" "$dir/seeds/obj" "$dir/seeds/model" || exit 1
mkdir -p "$dir/artifacts"
bad=0
for h in obj model; do
    mkdir -p "$dir/corpus_$h"
    log="$dir/fuzz_$h.log"
    # -timeout 120 (wall clock): a slow unit is a finding, but the pipeline under ASan takes
    # seconds of CPU on some inputs (Coons–Gregory evaluation) and a shared machine stretches that
    "$dir/fuzz_$h" -max_total_time="$secs" -timeout=120 -rss_limit_mb=2048 -max_len=4096 \
        -dict="$here/obj.dict" -artifact_prefix="$dir/artifacts/$h-" -print_final_stats=1 \
        "$dir/corpus_$h" "$dir/seeds/$h" > "$log" 2>&1
    rc=$?
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1)
    units=$(ls "$dir/corpus_$h" | wc -l)
    if [ "$rc" -eq 0 ]; then
        echo "fuzz_$h: ${execs:-?} executions in ${secs} s, ${cov:-cov: ?}, corpus $units inputs: no findings"
    else
        bad=1
        echo "fuzz_$h: FINDING after ${execs:-?} executions (exit $rc); input saved in $dir/artifacts/, log $log:"
        grep -E 'ERROR|invariant|SUMMARY|Test unit written' "$log" | head -n 8
    fi
done
exit $bad
