#!/bin/sh
# Runs the studies that reproduce Chen et al. 2014 and Guo & Yang 2005
# through the campaign and puts their numbers beside the papers'
# (docs/reproduction.md; `make reproduce` calls this).
#   usage: sh studies/reproduce.sh [quick|full|check] BINDIR [DIR] [OUT]
#     quick  the quick variants (small bars, one grid each): about half an
#            hour on one idle core
#     full   the papers' sizes and sweeps: many hours (the Cu1052 impacts
#            alone take hours each); resumes where it stopped
#     check  runs nothing: every study of both modes must plan, and every
#            row's job selector must pick exactly one job of a study that
#            records the metric (make test runs this)
#     BINDIR holds cascade and cascade-solver
#     DIR    results database and run directories (runs/reproduce-MODE)
#     OUT    reports (reports/reproduce-MODE): one per study, and
#            summary.md / summary.csv with the papers' numbers beside ours
# What is compared comes from studies/reproduction.tsv.  Every study runs
# even when another failed; the exit status is 1 when any job failed or a
# number is missing, 2 on bad usage.
set -u
USAGE="usage: reproduce.sh [quick|full|check] BINDIR [DIR] [OUT]"
MODE=${1:-quick}
case "$MODE" in
    quick) COL=4 ;;
    full) COL=5 ;;
    check) COL= ;;
    *) echo "$USAGE" >&2; exit 2 ;;
esac
[ $# -ge 2 ] || { echo "$USAGE" >&2; exit 2; }
BIN=$(cd "$2" && pwd) || exit 2
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DIR=${3:-$ROOT/runs/reproduce-$MODE}
OUT=${4:-$ROOT/reports/reproduce-$MODE}
SPEC=${REPRODUCE_SPEC:-$ROOT/studies/reproduction.tsv}
CASCADE=$BIN/cascade
export CASCADE_SOLVER="$BIN/cascade-solver"
for f in "$CASCADE" "$CASCADE_SOLVER"; do
    [ -x "$f" ] || { echo "reproduce.sh: $f: not an executable (run make first)" >&2; exit 2; }
done
mkdir -p "$DIR" "$OUT" || exit 1
DB=$DIR/cascade.db
TAB=$(printf '\t')
status=0

# The rows of the spec: comments and the header line left out.
rows() { grep -v '^#' "$SPEC" | sed 1d; }

study_name() { sed -n 's/^name:[[:space:]]*//p' "$1" | head -n 1; }

# 2. The rows of one job as CSV without header: "value,unit" of a metric
#    from the results view, or (check) the job's id from the jobs table.
#    Selector: `-` or `sweep` (the study's only sweep job), `prep:NAME`,
#    or `key=value;key=value` (swept values; numbers compare as numbers).
#    Every value is bound as a parameter, never pasted into the SQL.
select_job() { # select_job results|jobs STUDY METRIC SELECTOR
    if [ "$1" = results ]; then
        sql="SELECT value, unit FROM results r WHERE r.study = :study AND r.metric = :metric"
        args="--param study=$2 --param metric=$3"
    else
        sql="SELECT r.job_id FROM (SELECT j.id AS job_id, j.kind, j.name AS job_name,
                 s.name AS study FROM jobs j JOIN studies s ON s.id = j.study_id
                 WHERE j.active = 1) r WHERE r.study = :study"
        args="--param study=$2"
    fi
    case "$4" in
        -|sweep) sql="$sql AND r.kind = 'sweep'" ;;
        prep:*) sql="$sql AND r.kind = 'prep' AND r.job_name = :prep"
                args="$args --param prep=${4#prep:}" ;;
        *) i=0
           rest=$4
           while [ -n "$rest" ]; do
               pair=${rest%%;*}
               if [ "$pair" = "$rest" ]; then rest=; else rest=${rest#*;}; fi
               i=$((i + 1))
               sql="$sql AND EXISTS (SELECT 1 FROM job_params p WHERE p.job_id = r.job_id
                        AND p.name = :k$i AND (p.value = :v$i OR p.value = CAST(:v$i AS TEXT)))"
               args="$args --param k$i=${pair%%=*} --param v$i=${pair#*=}"
           done ;;
    esac
    # args holds --param NAME=VALUE words without blanks: split on purpose
    # shellcheck disable=SC2086
    "$CASCADE" query "$sql" --db "$DB" --csv $args 2>/dev/null | sed 1d
}

# The job selector of a row for a mode: `QUICK|FULL` or one for both.
mode_job() { # mode_job quick|full SELECTOR
    case "$2" in
        *"|"*) if [ "$1" = quick ]; then echo "${2%%|*}"; else echo "${2#*|}"; fi ;;
        *) echo "$2" ;;
    esac
}

# The metrics a study records (its `metrics:` list, one name per line).
study_metrics() {
    awk '/^metrics:/ { on = 1 } on { print } on && /\]/ { exit }' "$1" |
        sed 's/^metrics://' | tr -d '[] ' | tr ',' '\n' | grep .
}

# A finite decimal number (no nan, inf or hex).
is_number() { printf '%s' "$1" | grep -Eq '^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$'; }

if [ "$MODE" = check ]; then
    bad=0
    line=0
    seen=
    for m in quick full; do
        [ $m = quick ] && c=4 || c=5
        for s in $(rows | cut -f "$c" | grep -v '^-$' | awk '!seen[$0]++'); do
            [ -f "$ROOT/studies/$s" ] || { echo "$SPEC: $s: no such study" >&2; bad=1; continue; }
            "$CASCADE" plan "$ROOT/studies/$s" --register --db "$DB" >/dev/null ||
                { echo "$SPEC: $s: does not plan" >&2; bad=1; }
        done
    done
    tmp=$DIR/.rows
    rows > "$tmp"
    while IFS="$TAB" read -r paper where quantity quick full job metric pval unit note; do
        line=$((line + 1))
        if [ -z "$note" ] || [ -z "$paper" ] || [ -z "$quantity" ] || [ -z "$unit" ]; then
            echo "$SPEC: row $line: needs 10 tab-separated fields (paper ... note), none empty" >&2
            bad=1
            continue
        fi
        if [ "$pval" != "-" ] && ! is_number "$pval"; then
            echo "$SPEC: row $line ($quantity): paper_value '$pval' is neither - nor a finite number" >&2
            bad=1
        fi
        if printf '%s\n' "$seen" | grep -qxF "$paper $quantity"; then
            echo "$SPEC: row $line ($quantity): the same quantity of $paper twice" >&2
            bad=1
        fi
        seen="$seen
$paper $quantity"
        for m in quick full; do
            [ $m = quick ] && s=$quick || s=$full
            [ "$s" = "-" ] && continue
            [ -f "$ROOT/studies/$s" ] || continue
            name=$(study_name "$ROOT/studies/$s")
            sel=$(mode_job $m "$job")
            n=$(select_job jobs "$name" "$metric" "$sel" | grep -c .)
            if [ "$n" -ne 1 ]; then
                echo "$SPEC: row $line ($quantity): job '$sel' picks $n jobs of $s ($m), not one" >&2
                bad=1
            fi
            if ! study_metrics "$ROOT/studies/$s" | grep -qx "$metric"; then
                echo "$SPEC: row $line ($quantity): $s does not record $metric ($m)" >&2
                bad=1
            fi
        done
    done < "$tmp"
    rm -f "$tmp"
    [ $bad = 0 ] && echo "reproduce.sh: $SPEC: $line rows, every study plans and every row picks one job"
    exit $bad
fi

# 1. Run every study the mode names, in the order of the spec.
studies=$(rows | cut -f "$COL" | grep -v '^-$' | awk '!seen[$0]++')
for s in $studies; do
    file=$ROOT/studies/$s
    name=$(study_name "$file")
    [ -n "$name" ] || { echo "reproduce.sh: $SPEC: $s has no name:" >&2; status=1; continue; }
    echo "== $s ($name)"
    start=$(date +%s)
    if ! "$CASCADE" run "$file" --db "$DB" --runs "$DIR/runs"; then
        echo "reproduce.sh: $s: some jobs failed (see cascade status $name --db $DB)" >&2
        status=1
    fi
    echo "   $(( $(date +%s) - start )) s"
    "$CASCADE" report "$name" --db "$DB" --out "$OUT/$name" >/dev/null ||
        { echo "reproduce.sh: report of $name failed" >&2; status=1; }
done

# 3. The table.
md=$OUT/summary.md
csv=$OUT/summary.csv
{
    echo "# Reproduction ($MODE): the papers' numbers beside ours"
    echo
    echo "Generated by \`make reproduce REPRODUCE=$MODE\` (studies/reproduce.sh) on"
    echo "$(date -u +%Y-%m-%dT%H:%M:%SZ), $("$CASCADE_SOLVER" --version 2>/dev/null | head -n 1)."
    echo "Rows and criteria: studies/reproduction.tsv; discussion: docs/reproduction.md."
    echo
    echo "Ours to four significant digits (summary.csv has every digit); the"
    echo "difference is (ours - paper) / paper where the paper gives a number."
    echo
    echo "| paper | where | quantity | paper | ours | difference | unit | study, job | note |"
    echo "|---|---|---|---|---|---|---|---|---|"
} > "$md"
echo "paper,where,quantity,paper_value,value,unit,study,job,metric" > "$csv"
missing=$OUT/.missing
: > "$missing"
rows | while IFS="$TAB" read -r paper where quantity quick full job metric pval unit note; do
    [ "$MODE" = quick ] && s=$quick || s=$full
    [ "$s" = "-" ] && continue
    job=$(mode_job "$MODE" "$job")
    name=$(study_name "$ROOT/studies/$s")
    got=$(select_job results "$name" "$metric" "$job" | tr ',' "$TAB")
    n=$(printf '%s\n' "$got" | grep -c .)
    if [ "$n" -eq 1 ]; then
        value=$(printf '%s' "$got" | cut -f 1)
        ounit=$(printf '%s' "$got" | cut -f 2)
        [ -n "$value" ] || value="(not a number)"
        [ "$ounit" = "$unit" ] || value="$value (unit $ounit)"
    elif [ "$n" -eq 0 ]; then
        value="missing"
        echo "reproduce.sh: no $metric for $name, job $job (failed or not run)" >&2
        echo "$name $metric" >> "$missing"
    else
        value="ambiguous ($n jobs)"
        echo "reproduce.sh: $SPEC: job selector '$job' matches $n jobs of $name" >&2
        echo "$name $metric" >> "$missing"
    fi
    shown=$value
    diff=-
    if is_number "$value"; then
        shown=$(awk -v v="$value" 'BEGIN { printf "%.4g", v }')
        is_number "$pval" && diff=$(awk -v v="$value" -v p="$pval" \
            'BEGIN { if (p != 0) printf "%+.1f %%", 100 * (v - p) / p; else print "-" }')
    fi
    echo "| $paper | $where | $quantity | $pval | $shown | $diff | $unit | $name, $job | $note |" >> "$md"
    printf '"%s","%s","%s","%s","%s","%s","%s","%s","%s"\n' "$paper" "$where" "$quantity" \
        "$pval" "$value" "$unit" "$name" "$job" "$metric" >> "$csv"
done
{
    echo
    echo "## Cost"
    echo
    echo "| study | jobs done | not done | wall seconds (sum) | peak memory (MiB, max) |"
    echo "|---|---|---|---|---|"
} >> "$md"
for s in $studies; do
    name=$(study_name "$ROOT/studies/$s")
    "$CASCADE" query "SELECT sum(state = 'done'), sum(state <> 'done'), round(sum(wall_s), 1),
                             round(max(peak_rss_mib), 1) FROM job_status WHERE study = :s" \
        --param "s=$name" --db "$DB" --csv 2>/dev/null | sed 1d |
        awk -F, -v n="$name" '{ printf "| %s | %s | %s | %s | %s |\n", n, $1, $2, $3, $4 }' >> "$md"
done
[ -s "$missing" ] && status=1
rm -f "$missing"
echo "reproduce.sh: $md"
exit $status
