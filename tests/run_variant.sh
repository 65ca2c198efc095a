#!/bin/sh
# run_variant.sh BUILD RUNNER TEST... - runs each test program of one build,
# keeps its output in BUILD/logs, and prints its lines and summary.
build=$1 runner=$2
shift 2
mkdir -p "$build/logs"
status=0
for t in "$@"; do
    name=$(basename "$t")
    # shellcheck disable=SC2086
    if (cd "$(dirname "$0")/.." && $runner "$t") > "$build/logs/$name.log" 2>&1; then :; else status=1; fi
    cat "$build/logs/$name.log"
    if ! tail -n 1 "$build/logs/$name.log" | grep -Eq '^[a-z_0-9]+: [0-9]+ passed, [0-9]+ failed$'; then
        echo "$name: 0 passed, 1 failed   (crashed or printed no summary)"
        status=1
    fi
done
exit $status
