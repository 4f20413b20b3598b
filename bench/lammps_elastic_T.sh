#!/bin/sh
# Cross-check of the isothermal cubic elastic constants at a temperature
# (our `type: elastic`, solver/scenarios/elastic_case.c) against LAMMPS on
# the same potential file, by the same route: finite +-strains of a
# periodic cubic crystal at a(T) under a Langevin bath, central differences
# of time-averaged pressures: diamond Si (sw, meam: 4^3 cells, 512 atoms)
# or bcc Fe (fe: Mendelev's Fe_mm.eam.fs, 6^3 cells, 432 atoms, the cells
# of docs/examples/elastic_fe_300K.yaml).  C11 and C12 from a uniaxial
# strain along x (sigma_xx and the mean of sigma_yy, sigma_zz); C44 from a
# tilt shear gamma_xy (sigma_xy) -- not the [110] strain ours uses, so C44
# is checked by another construction.  The atoms relax their sublattices
# freely: C44 is the relaxed one (diamond; bcc has no internal strain).  Not a timing benchmark (bench.sh does not
# run it); docs/handshake.md, "Cross-check against LAMMPS", has the numbers.
#
#   sh bench/lammps_elastic_T.sh sw|meam|fe A [EPS...]
#   e.g. SEEDS="1 2 3 4" NEQ=2000 NRUN=6000 NPT=1 sh bench/lammps_elastic_T.sh fe 2.85906
#
# A: the lattice constant at T (Å).  EPS: strain amplitudes (default 0.01).
# Environment: SEEDS (default "1 2"), T (300), NEQ (3000 steps), NRUN (10000
# steps, sampled every 10), DT (0.001 ps), TDAMP (0.5 ps), CELLS (per edge;
# 4 for Si, 6 for Fe), NPT (1: also one run per seed at P = 0 under a
# barostat, for LAMMPS' own a(T); 0), JOBS (runs at once, 1), WORK (kept
# when given; else a temporary directory).
# Prints one line per seed and strain and the mean over the seeds with the
# standard error of their spread (GPa), and the mean pressure of the four
# runs (P at a to O(eps^2)); with NPT=1 also a(T) per seed (block error)
# and their mean.
set -eu
pot=${1:?usage: lammps_elastic_T.sh sw|meam|fe A [EPS...]}
a=${2:?usage: lammps_elastic_T.sh sw|meam|fe A [EPS...]}
shift 2
EPS=${*:-0.01}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
POTDIR=${POTDIR:-/usr/share/lammps/potentials}
lattice=diamond; element=Si; mass=28.0855; cells=4
case "$pot" in
    sw) style=sw; file=$POTDIR/Si.sw ;;
    meam) style=meam/spline; file=$POTDIR/Si_1.meam.spline ;;
    fe) style=eam/fs; file=$POTDIR/Fe_mm.eam.fs; lattice=bcc; element=Fe; mass=55.845; cells=6 ;;
    *) echo "lammps_elastic_T.sh: potential sw, meam or fe, not $pot" >&2; exit 2 ;;
esac
CELLS=${CELLS:-$cells}; NPT=${NPT:-0}
SEEDS=${SEEDS:-1 2}
T=${T:-300}; NEQ=${NEQ:-3000}; NRUN=${NRUN:-10000}; DT=${DT:-0.001}; TDAMP=${TDAMP:-0.5}
JOBS=${JOBS:-1}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-lmp-elastic.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
mkdir -p "$WORK"
# one line per run: name mode eps seed; skipped when its samples exist
: > "$WORK/runs.txt"
for seed in $SEEDS; do
    for eps in $EPS; do
        for mode in x xy; do
            for sign in p m; do
                e=$eps; [ "$sign" = m ] && e=-$eps
                name=$pot-$mode-$sign$eps-s$seed
                [ -s "$WORK/$name.dat" ] || echo "$name $mode $e $seed" >> "$WORK/runs.txt"
            done
        done
    done
    name=$pot-npt-s$seed
    if [ "$NPT" = 1 ] && [ ! -s "$WORK/$name.dat" ]; then echo "$name npt 0 $seed" >> "$WORK/runs.txt"; fi
done
export WORK ROOT style file lattice element mass CELLS a T NEQ NRUN DT TDAMP
# shellcheck disable=SC2016
xargs -P "$JOBS" -L 1 sh -c 'cd "$WORK" && lmp -in "$ROOT/bench/lammps_elastic_T.in" \
    -log none -screen "$WORK/$0.out" -var style "$style" -var file "$file" -var a "$a" -var lattice "$lattice" \
    -var n "$CELLS" -var element "$element" -var mass "$mass" \
    -var mode "$1" -var eps "$2" -var T "$T" -var seed "$3" -var neq "$NEQ" -var nrun "$NRUN" \
    -var dt "$DT" -var tdamp "$TDAMP" -var out "$0.tmp" >/dev/null && mv "$0.tmp" "$0.dat"' \
    < "$WORK/runs.txt"
/usr/bin/python3 - "$WORK" "$pot" "$T" "$SEEDS" "$EPS" "$a" "$NPT" <<'EOF'
import math, sys
work, pot, T, seeds, epss = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4].split(), sys.argv[5].split()
def mean_block(x, nb=10):
    m = sum(x) / len(x)
    L = len(x) // nb
    b = [sum(x[k * L:(k + 1) * L]) / L for k in range(nb)]
    bm = sum(b) / nb
    return m, math.sqrt(sum((v - bm) ** 2 for v in b) / (nb - 1) / nb)
def run(mode, sign, eps, seed):
    rows = [list(map(float, l.split())) for l in open(f"{work}/{pot}-{mode}-{sign}{eps}-s{seed}.dat")
            if l.strip() and not l.startswith('#')]
    col = lambda k: [r[k] for r in rows]
    # bar -> GPa; the columns: step temp pxx pyy pzz pxy pxz pyz lx/n
    out = {k: mean_block([v * 1e-4 for v in col(i)]) for k, i in
           (("xx", 2), ("yy", 3), ("zz", 4), ("xy", 5))}
    out["yz2"] = mean_block([0.5e-4 * (r[3] + r[4]) for r in rows])
    out["T"] = mean_block(col(1))
    out["p"] = mean_block([(r[2] + r[3] + r[4]) / 3e4 for r in rows])
    return out
for eps in epss:
    e = float(eps)
    res = []
    for s in seeds:
        xp, xm, sp, sm = (run(m, g, eps, s) for m, g in (("x", "p"), ("x", "m"), ("xy", "p"), ("xy", "m")))
        d = lambda A, B, k: (-(A[k][0] - B[k][0]) / (2 * e), math.hypot(A[k][1], B[k][1]) / (2 * e))
        c11, c12, c44 = d(xp, xm, "xx"), d(xp, xm, "yz2"), d(sp, sm, "xy")
        p0 = sum(r["p"][0] for r in (xp, xm, sp, sm)) / 4
        tm = sum(r["T"][0] for r in (xp, xm, sp, sm)) / 4
        res.append((c11[0], c12[0], c44[0], p0))
        print(f"{pot} eps {eps} seed {s}: C11 {c11[0]:.2f} +- {c11[1]:.2f}  C12 {c12[0]:.2f} +- {c12[1]:.2f}"
              f"  C44 {c44[0]:.2f} +- {c44[1]:.2f} GPa (block errors); P {p0:.4f} GPa, T {tm:.1f} K")
    n = len(res)
    def ms(k):
        m = sum(r[k] for r in res) / n
        return m, (math.sqrt(sum((r[k] - m) ** 2 for r in res) / (n - 1) / n) if n > 1 else float("nan"))
    (m11, e11), (m12, e12), (m44, e44), (mp, ep) = ms(0), ms(1), ms(2), ms(3)
    print(f"{pot} eps {eps} mean of {n} seeds: C11 {m11:.2f} +- {e11:.2f}  C12 {m12:.2f} +- {e12:.2f}"
          f"  C44 {m44:.2f} +- {e44:.2f} GPa; P {mp:.4f} +- {ep:.4f} GPa at a = {sys.argv[6]} A")
if sys.argv[7] == "1":
    al = []
    for s in seeds:
        rows = [list(map(float, l.split())) for l in open(f"{work}/{pot}-npt-s{s}.dat")
                if l.strip() and not l.startswith('#')]
        m, e = mean_block([r[8] for r in rows])
        p, pe = mean_block([(r[2] + r[3] + r[4]) / 3e4 for r in rows])
        tm = mean_block([r[1] for r in rows])[0]
        al.append(m)
        print(f"{pot} P = 0 seed {s}: a {m:.5f} +- {e:.5f} A (block error); P {p:.4f} +- {pe:.4f} GPa, T {tm:.1f} K")
    n = len(al)
    m = sum(al) / n
    e = math.sqrt(sum((v - m) ** 2 for v in al) / (n - 1) / n) if n > 1 else float("nan")
    print(f"{pot} P = 0 mean of {n} seeds: a {m:.5f} +- {e:.5f} A (ours given: {sys.argv[6]} A)")
EOF
