#!/bin/sh
# run_variant.sh BUILD RUNNER TEST... - runs each test program of one build,
# keeps its output in BUILD/logs, and prints its lines and summary in the
# order given. JOBS (default 2) programs run at once (none measures time).
build=$1 runner=$2
shift 2
jobs=${JOBS:-2}
mkdir -p "$build/logs"
cd "$(dirname "$0")/.." || exit 1
# shellcheck disable=SC2016 # expanded by the inner sh; $2 (the runner) is a word list
printf '%s\n' "$@" | xargs -P "$jobs" -I{} sh -c '
    name=$(basename "$1")
    if $2 "$1" > "$0/logs/$name.log" 2>&1; then echo 0; else echo 1; fi > "$0/logs/$name.rc"
' "$build" {} "$runner"
status=0
for t in "$@"; do
    name=$(basename "$t")
    [ "$(cat "$build/logs/$name.rc" 2>/dev/null)" = 0 ] || status=1
    cat "$build/logs/$name.log"
    if ! tail -n 1 "$build/logs/$name.log" | grep -Eq '^[a-z_0-9]+: [0-9]+ passed, [0-9]+ failed$'; then
        echo "$name: 0 passed, 1 failed   (crashed or printed no summary)"
        status=1
    fi
done
exit $status
