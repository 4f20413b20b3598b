#!/bin/sh
# Seed the fuzz corpora (tests/fuzz/corpus/<reader>/) from real inputs: the
# example cases and studies, the test data, a solver result, the baselines
# and the potential files of Debian's lammps-data package -- large tables
# resampled to 24 knots so every seed stays small.  `make fuzz` grows the
# corpora from here; rerunning this script only rewrites the seed-* files.
#
#   sh fuzz/seed.sh [SOLVER]     (SOLVER: a cascade-solver for result.json;
#                                 default bin/cascade-solver)
set -eu
cd "$(dirname "$0")/.."
C=tests/fuzz/corpus
POT=${CASCADE_POTENTIALS:-/usr/share/lammps/potentials}
SOLVER=${1:-bin/cascade-solver}
for r in case study lammps_data extxyz eam sw meam_spline result_json baseline; do
    mkdir -p "$C/$r"
    rm -f "$C/$r"/seed-*
done

# --- case: the examples, the chen2014 cases, one JSON case (resolve --batch)
for f in docs/examples/*.yaml studies/chen2014/cases/*.yaml; do
    cp "$f" "$C/case/seed-$(basename "$f" .yaml).yaml"
done
printf '%s\n' '{"system": {"lattice": {"style": "fcc", "a": 3.615, "cells": [2, 2, 2]}, "element": "Cu"}, "potential": {"style": "sutton_chen"}, "md": {"timestep": 0.001, "steps": 10}}' \
    > "$C/case/seed-batch.json"

# --- study: every study, bases named by file pointed at the harness's case.yaml
for f in studies/*.yaml studies/*/*.yaml; do
    n=$(echo "$f" | sed 's|^studies/||; s|/|_|g; s|\.yaml$||')
    sed -E 's/^( *base:) *[^ {#][^ #]*\.yaml/\1 case.yaml/' "$f" > "$C/study/seed-$n.yaml"
done

# --- LAMMPS data: the test configurations cut to 6 atoms, and variants
cut_data() {   # file natoms
    awk -v n="$2" '
        / atoms$/ { print n " atoms"; next }
        /^Atoms/ { print; atoms = 1; next }
        atoms && NF >= 5 { if (++k > n) exit }
        { print }' "$1"
}
cut_data tests/data/cu256.data 6 > "$C/lammps_data/seed-cu.data"
cut_data tests/data/si216.data 6 > "$C/lammps_data/seed-si.data"
cat > "$C/lammps_data/seed-cuni-vel.data" <<'D'
CuNi with image flags and velocities

3 atoms
2 atom types

0.0 7.23 xlo xhi
-1.0 6.23 ylo yhi
0 7.23 zlo zhi

Masses

1 63.546 # Cu
2 58.6934 # Ni

Atoms # atomic

1 1 0.0 0.0 0.0 0 0 0
2 2 1.8075 1.8075 0.0 1 0 -1
3 1 1.8075 0.0 1.8075 0 0 0

Velocities

1 0.1 0.2 0.3
3 -1.0 0.0 2.5
2 0 0 0
D
cat > "$C/lammps_data/seed-triclinic-zero.data" <<'D'
LAMMPS data file via write_data of a prism region of tilt 0 0 0

2 atoms
1 atom types

0.0000000000000000e+00 7.2300000000000000e+00 xlo xhi
0.0000000000000000e+00 7.2300000000000000e+00 ylo yhi
0.0000000000000000e+00 7.2300000000000000e+00 zlo zhi
0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00 xy xz yz

Masses

1 63.546

Atoms # atomic

1 1 0.0000000000000000e+00 0.0000000000000000e+00 0.0000000000000000e+00 0 0 0
2 1 1.8075000000000001e+00 1.8075000000000001e+00 0.0000000000000000e+00 0 0 0

Velocities

1 1.0 -2.0 0.5
2 0 0 0
D
cat > "$C/lammps_data/seed-noname.data" <<'D'
LAMMPS data file without type names (system.elements names them)

2 atoms
2 atom types
0 10 xlo xhi
0 10 ylo yhi
0 10 zlo zhi

Atoms

1 1 1 1 1
2 2 2.5 1 1
D

# --- extended XYZ
cat > "$C/extxyz/seed-cu.xyz" <<'D'
3
Lattice="7.23 0.0 0.0 0.0 7.23 0.0 0.0 0.0 7.23" Properties=species:S:1:pos:R:3:vel:R:3:id:I:1 pbc="T T F" Time=0.5
Cu 0.0 0.0 0.0 0.1 0.2 0.3 1
Cu 1.8075 1.8075 0.0 0 0 0 2
Ni 1.8075 0.0 1.8075 -1 0 2.5 7
D
cat > "$C/extxyz/seed-plain.xyz" <<'D'
2
Lattice="10 0 0 0 10 0 0 0 10" Origin="-5 -5 -5"
Si 0 0 0
Si 1.2 1.3 -4.5
D
cat > "$C/extxyz/seed-ase-momenta.xyz" <<'D'
2
Lattice="7.23 0.0 0.0 0.0 7.23 0.0 0.0 0.0 7.23" Properties=species:S:1:pos:R:3:masses:R:1:momenta:R:3:forces:R:3 pbc="T T T"
Cu 0.0 0.0 0.0 63.546 0.5 -0.25 0.0 0.1 0 0
Cu 1.8075 1.8075 0.0 63.546 -0.5 0.25 0.0 -0.1 0 0
D

# --- EAM: funcfl, setfl and fs files resampled to 24 knots
resample() {   # file format(funcfl|setfl|fs) knots
    awk -v fmt="$2" -v N="$3" '
    function flush(   i) { for (i = 1; i <= nb; i++) printf "%s%s", buf[i], (i % 5 == 0 || i == nb) ? "\n" : " "; nb = 0 }
    function table(n, s,   i, v) { for (i = 0; i < n; i++) { v = tok(); if (i % s == 0 && i / s < N) buf[++nb] = v } flush() }
    function tok() { while (p > nt) { if ((getline line) <= 0) return ""; nt = split(line, t); p = 1 } return t[p++] }
    BEGIN {
        p = 1; nt = 0
        nh = fmt == "funcfl" ? 1 : 3
        for (i = 0; i < nh; i++) { getline line; print line }
        if (fmt == "funcfl") { getline line; print line; ne = 1 }
        else { getline line; print line; split(line, h); ne = h[1] }
        nrho = tok(); drho = tok(); nr = tok(); dr = tok(); cut = tok()
        sr = int((nrho - 1) / (N - 1)); sd = int((nr - 1) / (N - 1))
        printf "%d %.16g %d %.16g %s\n", N, drho * sr, N, dr * sd, cut
        if (fmt == "funcfl") { table(nrho, sr); table(nr, sd); table(nr, sd); exit }
        for (a = 0; a < ne; a++) {
            printf "%s %s %s %s\n", tok(), tok(), tok(), tok()
            table(nrho, sr)
            for (b = 0; b < (fmt == "fs" ? ne : 1); b++) table(nr, sd)
        }
        for (a = 0; a < ne; a++) for (b = 0; b <= a; b++) table(nr, sd)
    }' < "$1"
}
resample "$POT/Cu_u3.eam" funcfl 24 > "$C/eam/seed-Cu_u3.eam"
resample "$POT/Cu_mishin1.eam.alloy" setfl 24 > "$C/eam/seed-Cu_mishin1.eam.alloy"
resample "$POT/CuNi.eam.alloy" setfl 24 > "$C/eam/seed-CuNi.eam.alloy"
resample "$POT/Fe_mm.eam.fs" fs 24 > "$C/eam/seed-Fe_mm.eam.fs"
resample "$POT/AlFe_mm.eam.fs" fs 24 > "$C/eam/seed-AlFe_mm.eam.fs"

# --- Stillinger-Weber: the files as they are (small)
for f in Si.sw GaN.sw CdTe.sw; do cp "$POT/$f" "$C/sw/seed-$f"; done
# (GaN.sw and CdTe.sw have sigma = a = 0 in their pure three-body entries,
#  which the reader refuses today; this one reads as Ga N)
grep -v '^#' "$POT/GaN.sw" | awk 'NF == 14 && $5 == 0 { $5 = 1.695; $6 = 1.8; $8 = 1.2; $10 = 7.917; $11 = 0.72; $12 = 4.0 } NF == 14 { print }' \
    > "$C/sw/seed-GaN-positive.sw"

# --- meam/spline: old format as is, and Si_1 rewritten in the new format
for f in Si_1.meam.spline Si_2.meam.spline; do cp "$POT/$f" "$C/meam_spline/seed-$f"; done
awk 'NR == 1 { print "# Si_1 in the new (spline3eq) format"; print "meam/spline 1 Si"; next }
     /^[01] [01] [01] [01]$/ { next }
     NF == 1 { print "spline3eq" }
     { print }' "$POT/Si_1.meam.spline" > "$C/meam_spline/seed-Si_1-new.meam.spline"

# --- result.json: a real one, and a diverged one with a non-ASCII message
if [ -x "$SOLVER" ]; then
    tmp=$(mktemp -d)
    printf 'title: tiny\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [2, 2, 2]}\n  element: Cu\npotential: {style: sutton_chen}\nmd: {timestep: 0.001, steps: 10}\noutput: {hdf5: false}\n' > "$tmp/tiny.yaml"
    "$SOLVER" run "$tmp/tiny.yaml" --out "$tmp/out" --quiet
    cp "$tmp/out/result.json" "$C/result_json/seed-ok.json"
    rm -rf "$tmp"
fi
cat > "$C/result_json/seed-diverged.json" <<'D'
{"status": "diverged", "message": "step 120: particle 17 moved 9.3 Å in one step (Δt too large?)",
 "metrics": {"pe": {"value": -3.5, "unit": "eV"}, "pressure": {"value": null, "unit": "GPa"}},
 "provenance": {"version": "0.1.0", "git_hash": "abcdef012345"}}
D

# --- baselines: as they are (a few kB)
for f in studies/baselines/*.json; do cp "$f" "$C/baseline/seed-$(basename "$f")"; done

du -sh "$C"/*
