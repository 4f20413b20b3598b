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
#   json_cpu FILE TIMER       CPU seconds of the loop or the whole run (loop,
#                             total) from a result.json: less moved by the
#                             machine's load than the wall time
#   lmp_loop_cpu OUT          LAMMPS' loop CPU seconds from its screen output
#                             ("Loop time of T" x "P% CPU use")
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

json_cpu() { # json_cpu RESULT.json loop|total -> CPU seconds
    tr -d ' \n' < "$1" | grep -o '"cpu_seconds":{[^}]*}' | grep -o "\"$2\":[0-9.eE+-]*" | sed 's/.*://'
}

lmp_loop_cpu() { # lmp_loop_cpu SCREEN.out -> CPU seconds of the loop
    awk '/^Loop time of/ {t = $4} /% CPU use/ {c = $1} END {sub("%", "", c); printf "%.6f\n", t * c / 100}' "$1"
}

json_timer() { # json_timer RESULT.json TIMER -> seconds
    tr -d ' \n' < "$1" | grep -o "\"$2\":{\"calls\":[0-9]*,\"seconds\":[0-9.eE+-]*" | sed 's/.*"seconds"://'
}

# The STREAM-like probe (bench/stream_probe.c), built once per bench run into
# WORK with the release flags; prints "copy_gbs triad_gbs" for arrays of
# MIB each (default 64: three arrays of 192 MiB in all, past the 2 x 4 MiB
# of L2 and twice the MPM benchmark's working set).  The best of 3 probes.
bench_stream() { # bench_stream [MIB]
    probe="$WORK/stream_probe"
    if [ ! -x "$probe" ]; then
        ${CC_PROBE:-cc} -std=c11 -O3 -march=native -o "$probe" "$ROOT/bench/stream_probe.c" >&2 || return 1
    fi
    k=0
    : > "$WORK/stream.$$"
    while [ $k -lt 3 ]; do
        k=$((k + 1))
        "$probe" "${1:-64}" 10 >> "$WORK/stream.$$"
    done
    sort -k2 -g "$WORK/stream.$$" | tail -n1
    rm -f "$WORK/stream.$$"
}

# Triad bandwidth (GB/s) for the roofline figures: BENCH_STREAM_GBS when
# bench.sh measured it already, else measured now.
bench_stream_gbs() {
    if [ -n "${BENCH_STREAM_GBS:-}" ]; then
        echo "$BENCH_STREAM_GBS"
    else
        bench_stream 64 | awk '{print $2}'
    fi
}

# Pairs of fcc lattice sites closer than R (Å) in a block of NX x NY x NZ
# cubic cells of edge A (Å), all directions free (periodic: every site has
# its full shell, pass p for PERIODIC).  Perfect lattice, each pair once.
#   fcc_pairs A R NX NY NZ [p]
fcc_pairs() {
    awk -v a="$1" -v R="$2" -v nx="$3" -v ny="$4" -v nz="$5" -v per="${6:-}" 'BEGIN {
        m = int(2 * R / a) + 1; n[0] = 2 * nx; n[1] = 2 * ny; n[2] = 2 * nz; total = 0
        for (p = -m; p <= m; p++) for (q = -m; q <= m; q++) for (r = -m; r <= m; r++) {
            if ((p + q + r) % 2 != 0) continue
            if (p < 0 || (p == 0 && q < 0) || (p == 0 && q == 0 && r <= 0)) continue
            if ((p * p + q * q + r * r) * a * a / 4 >= R * R) continue
            if (per == "p") { total += 4 * nx * ny * nz; continue }
            ilo = p < 0 ? -p : 0; ihi = p > 0 ? n[0] - p : n[0]
            jlo = q < 0 ? -q : 0; jhi = q > 0 ? n[1] - q : n[1]
            klo = r < 0 ? -r : 0; khi = r > 0 ? n[2] - r : n[2]
            for (i = ilo; i < ihi; i++) for (j = jlo; j < jhi; j++) {
                # k in [klo, khi) with i + j + k even
                k0 = klo + ((i + j + klo) % 2)
                if (k0 < khi) total += int((khi - 1 - k0) / 2) + 1
            }
        }
        print total
    }'
}
