# bench/lib.sh: what every bench script shares (sourced, POSIX sh).
#
#   bench_line NAME VALUE UNIT [ANCHOR]
#       prints "BENCH NAME VALUE UNIT (ANCHOR)" and, when BENCH_RECORD names
#       a file, appends the figure to it as one JSON object per line;
#       bench/bench.sh turns those lines into bench.json.  The anchor is what
#       the figure is to be read against: a target ("target 75"), a peer
#       measured in the same run ("LAMMPS 1.16 us") or a physical limit.
#   median              median of the numbers on stdin, one a line
#   bench_load          "load L1 L5 L15 on N cores": say it beside every timing
#   json_number FILE KEY      a metric's value from a result.json
#   json_timer FILE TIMER     a timer's seconds from a result.json
#
# A new benchmark is a bench/bench_NAME.sh that sources this file (with
# . "$ROOT/bench/lib.sh"), reports through bench_line, and is added to the
# list at the end of bench/bench.sh with one line.

median() { sort -g | awk '{a[NR]=$1} END {if (NR%2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2}'; }

bench_load() { echo "load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null) on $(nproc --all) cores"; }

# JSON string contents: backslashes and double quotes escaped, control
# characters dropped (anchors are short prose).
bench_json_str() { printf '%s' "$1" | tr -d '\000-\037' | sed 's/\\/\\\\/g; s/"/\\"/g'; }

bench_line() { # bench_line NAME VALUE UNIT [ANCHOR]
    if [ -n "${4:-}" ]; then
        echo "BENCH $1 $2 $3 ($4)"
    else
        echo "BENCH $1 $2 $3"
    fi
    if [ -n "${BENCH_RECORD:-}" ]; then
        case "$2" in   # a value that is not a number is recorded as null
            ''|*[!0-9eE.+-]*) v=null ;;
            *) v=$2 ;;
        esac
        printf '{"name": "%s", "value": %s, "unit": "%s", "anchor": "%s"}\n' \
            "$(bench_json_str "$1")" "$v" "$(bench_json_str "$3")" "$(bench_json_str "${4:-}")" \
            >> "$BENCH_RECORD"
    fi
}

json_number() { # json_number RESULT.json METRIC -> its value
    tr -d ' \n' < "$1" | grep -o "\"$2\":{\"unit\":\"[^\"]*\",\"value\":[-0-9.eE+]*" | sed 's/.*"value"://'
}

json_timer() { # json_timer RESULT.json TIMER -> seconds
    tr -d ' \n' < "$1" | grep -o "\"$2\":{\"calls\":[0-9]*,\"seconds\":[0-9.eE+-]*" | sed 's/.*"seconds"://'
}
