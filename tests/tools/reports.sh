# shellcheck shell=sh
# reports.sh - sourced by the stages that run one task per item, several at
# once (stage_cross.sh, stage_fuzz.sh):
#   reports_run SELF HEAD TAIL KIND NAME...
# runs `sh SELF --one NAME` for every NAME, JOBS (default 2) at once; the task
# writes its report lines to the file HEAD NAME TAIL. The reports are printed
# whole in the list's order (not interleaved), and their "ok   KIND..." and
# "FAIL KIND..." lines are added to the caller's pass and fail. A report that
# is missing is a failure.
reports_run() {
    rr_self=$1 rr_head=$2 rr_tail=$3 rr_kind=$4
    shift 4
    for rr_name in "$@"; do rm -f "$rr_head$rr_name$rr_tail"; done
    printf '%s\n' "$@" | xargs -P "${JOBS:-2}" -I{} sh "$rr_self" --one {}
    for rr_name in "$@"; do
        rr_file=$rr_head$rr_name$rr_tail
        if [ -r "$rr_file" ]; then
            cat "$rr_file"
            pass=$((pass + $(grep -c "^ok   $rr_kind" "$rr_file")))
            fail=$((fail + $(grep -c "^FAIL $rr_kind" "$rr_file")))
        else
            echo "FAIL $rr_kind$rr_name (it did not report: $rr_file is missing)"
            fail=$((fail + 1))
        fi
    done
}
