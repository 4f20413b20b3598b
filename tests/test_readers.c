/*
 * The file readers of cascade-solver on bad input (issue 16, items 5, 6
 * and 8): each kind of defect of each reader is refused by `check` with
 * exit code 2 and a message naming file:line and the field; quoted file
 * text is cut to 40 characters; cases that would build more particles than
 * the limit are refused by `check` and `resolve`, and cutoffs that would
 * need astronomically many periodic images by `check`, in well under a
 * second.
 *
 * Each table row takes a valid file, replaces one line and states the
 * message expected; the valid file itself is checked first, so a row fails
 * for its own defect only.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/units.h"
#include "helpers/th.h"
#include "input/config_read.h"

/* --- helpers ---------------------------------------------------------------- */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* cascade-solver <cmd> bad.yaml [extra] on the case text; exit code, output
 * in out, wall time in *secs (may be NULL). */
static int solver(const char *cmd, const char *yaml, const char *extra, char *out, size_t len,
                  double *secs)
{
    const char *path = th_write_temp(1, "bad.yaml", yaml);
    const char *argv[] = {th_solver(), cmd, path, extra, NULL};
    double t0 = now();
    int rc = th_run(argv, out, len);
    if (secs)
        *secs = now() - t0;
    return rc;
}

/* text with line `line` (1-based) replaced by `repl` (NULL: text as is);
 * `repl` may hold several lines.  Static storage, one at a time. */
static const char *with_line(const char *text, int line, const char *repl)
{
    static char buf[65536];
    if (!repl || line < 1) {
        snprintf(buf, sizeof buf, "%s", text);
        return buf;
    }
    const char *s = text;
    for (int k = 1; k < line && s; k++) {
        s = strchr(s, '\n');
        if (s)
            s++;
    }
    cr_assert_not_null(s, "line %d beyond the text", line);
    const char *end = strchr(s, '\n');
    snprintf(buf, sizeof buf, "%.*s%s%s", (int)(s - text), text, repl, end ? end : "\n");
    return buf;
}

struct row {
    int line;              /* line to replace */
    const char *repl;      /* its new text */
    const char *expect;    /* substring of the message */
};

/* Write the file `name` with each row's change, run check on the case made
 * by case_fmt (one %s: the file's path) and assert exit 2 and the message.
 * Row 0 of the caller's table is not special: the valid file is checked
 * here first, with exit 0. */
static void run_table(const char *name, const char *valid, const char *case_fmt,
                      const struct row *rows, size_t nrows)
{
    char yaml[4096], out[8192];
    const char *path = th_write_temp(2, name, valid);
    snprintf(yaml, sizeof yaml, case_fmt, path);
    int rc = solver("check", yaml, NULL, out, sizeof out, NULL);
    cr_assert_eq(rc, 0, "the valid %s must pass: %s", name, out);
    for (size_t k = 0; k < nrows; k++) {
        th_write_temp(2, name, with_line(valid, rows[k].line, rows[k].repl));
        rc = solver("check", yaml, NULL, out, sizeof out, NULL);
        cr_assert_eq(rc, 2, "%s line %d '%.60s': exit %d: %s", name, rows[k].line, rows[k].repl,
                     rc, out);
        cr_assert(strstr(out, rows[k].expect), "%s line %d '%.60s':\n  expected: %s\n  got: %s",
                  name, rows[k].line, rows[k].repl, rows[k].expect, out);
        /* file text quoted in a message is cut short: no message grows with
         * the file (the longest row below quotes 40 of 200 characters) */
        cr_assert_lt(strlen(out), 700, "message too long: %s", out);
    }
}

static char long_token[256];

static void init_long_token(void)
{
    memset(long_token, 'x', 200);
    long_token[0] = '1';
    long_token[200] = '\0';
}

/* "1xxx...x" cut to 40 characters */
#define LONG_EXCERPT "'1xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx...'"

/* --- LAMMPS data ------------------------------------------------------------ */

/* lines 15-17 are the atoms, 21-23 the velocities */
#define DATA_OK                                                                                   \
    "title\n\n3 atoms\n1 atom types\n0 14 xlo xhi\n0 14 ylo yhi\n0 14 zlo zhi\n\nMasses\n\n"     \
    "1 63.5 # Cu\n\nAtoms # atomic\n\n1 1 1 1 1\n2 1 3 3 3\n3 1 5 5 5\n\nVelocities\n\n"         \
    "1 0 0 0\n2 0 0 0\n3 0 0 0\n"
#define DATA_CASE "system:\n  read_data: %s\npotential: {style: sutton_chen}\n"

Test(readers, lammps_data_bad_input)
{
    init_long_token();
    char longline[300];
    snprintf(longline, sizeof longline, "3 1 %s 5 5", long_token);
    const struct row rows[] = {
        /* ids unique, both lines named */
        {16, "1 1 3 3 3", "m.data:16: Atoms: atom id 1 is given twice (also at line 15)"},
        {17, "2 1 5 5 5", "m.data:17: Atoms: atom id 2 is given twice (also at line 16)"},
        {22, "1 0 0 0", "m.data:22: Velocities: atom id 1 is given twice (also at line 21)"},
        {22, "7 0 0 0", "m.data:22: velocity for unknown atom id 7"},
        /* coordinates: within one box length of a periodic box */
        {16, "2 1 1e300 3 3", "m.data:16: atom id 2: x = 1e+300 is more than one box length "
                              "outside the box [0, 14) (periodic boundary along x)"},
        {16, "2 1 3 -14.5 3", "m.data:16: atom id 2: y = -14.5 is more than one box length"},
        {16, "2 1 3 3 28", "m.data:16: atom id 2: z = 28 is more than one box length"},
        /* coincident atoms, also across the periodic boundary */
        {16, "2 1 1 1 1", "m.data:16: atom id 2 at (1, 1, 1) is 0 Å from atom id 1 at line 15: "
                          "atoms closer than 0.1 Å"},
        {16, "2 1 1.05 1 1", "m.data:16: atom id 2 at (1.05, 1, 1) is 0.05 Å from atom id 1"},
        {17, "3 1 14.98 1 1", "m.data:17: atom id 3 at (14.98, 1, 1) is 0.02 Å from atom id 1 "
                              "at line 15"},
        {17, "3 1 -12.95 14.95 1", "m.data:17: atom id 3 at (-12.95, 14.95, 1) is 0.0707 Å"},
        /* numbers are whole decimal tokens */
        {3, "3x atoms", "m.data:3: 'atoms' needs a count >= 0, found '3x'"},
        {4, "1.0 atom types", "m.data:4: 'atom types' needs a count >= 0, found '1.0'"},
        {3, "100000000 atoms", "m.data:3: 100000000 atoms are more than the limit of 20000000"},
        {5, "0 1e999 xlo xhi", "m.data:5: xlo xhi: box bounds must be finite decimal numbers"},
        {6, "0 14 ylo yhi extra", "m.data:6: unrecognised header line '0 14 ylo yhi extra'"},
        {11, "1.5 63.5 # Cu", "m.data:11: Masses line must be 'type mass' with type 1..1"},
        {11, "1 63.5 # CuCuCuCuCuCuCuCuCu", "m.data:11: Masses: type name 'CuCuCuCuCuCuCuCuCu' "
                                            "is longer than 15 characters"},
        {16, longline, "m.data:16: Atoms line: field 3 (x) must be a finite decimal number, "
                       "found " LONG_EXCERPT},
        {21, "1 0 0 0x1", "m.data:21: Velocities line: field 4 (vz) must be a finite decimal"},
        {16, "2 1 3 3 3 0 0", "m.data:16: Atoms line must be 'id type x y z [ix iy iz]'"},
        /* triclinic boxes: LAMMPS' tilt limit (core/box.h) */
        {8, "0 7.5 0 xy xz yz", "m.data:8: xy xz yz: tilt xz = 7.5 is more than half the box "
                                "length lx = 14"},
        {8, "0 0 0x1 xy xz yz", "m.data:8: xy xz yz: tilt factor yz must be a finite decimal "
                                "number, found '0x1'"},
        {8, "0 0 xy xz yz", "m.data:8: unrecognised header line '0 0 xy xz yz' (a triclinic "
                            "box is 'xy xz yz' after its three tilt factors)"},
    };
    run_table("m.data", DATA_OK, DATA_CASE, rows, sizeof rows / sizeof rows[0]);
}

/* A triclinic header of zero tilt, as LAMMPS writes it for a prism region
 * of tilt 0 0 0, is the orthogonal box; ASE's momenta (with masses) give
 * the velocities of an extended XYZ file. */
Test(readers, zero_tilt_data_and_ase_momenta)
{
    char yaml[1024], out[4096];
    const char *data = th_write_temp(
        2, "m.data", with_line(DATA_OK, 8, "0.0000000000000000e+00 0 -0.0 xy xz yz"));
    snprintf(yaml, sizeof yaml, DATA_CASE, data);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
    struct particles *p = particles_create(8);
    struct box b = {0};
    struct err e = {0};
    cr_assert_eq(config_read_lammps_data(data, NULL, 0, NULL, p, &b, &e), 0, "%s", e.msg);
    cr_assert_eq(p->n_owned, 3);
    cr_assert_eq(b.hi[2], 14.0);
    particles_destroy(&p);
    /* momenta in amu Å / t_ASE, t_ASE = sqrt(UNITS_MVV2E) ps: v = p / (m t_ASE) */
    const char *xyz = th_write_temp(
        3, "ase.xyz",
        "2\nLattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:3:masses:R:1:"
        "momenta:R:3 pbc=\"T T T\"\nCu 1 1 1 50 1 -2 0.5\nCu 3 3 3 63.546 0 0 3\n");
    p = particles_create(8);
    int pbc[3];
    cr_assert_eq(config_read_extxyz(xyz, NULL, p, &b, pbc, &e), 0, "%s", e.msg);
    const double t_ase = sqrt(UNITS_MVV2E);
    const double want[2][3] = {{1 / (50 * t_ase), -2 / (50 * t_ase), 0.5 / (50 * t_ase)},
                               {0, 0, 3 / (63.546 * t_ase)}};
    for (int i = 0; i < 2; i++)
        for (int d = 0; d < 3; d++)
            cr_assert_lt(fabs(p->v[3 * i + d] - want[i][d]), 1e-12 * fabs(want[i][d]) + 1e-15,
                         "v[%d][%d] %.15g vs %.15g", i, d, p->v[3 * i + d], want[i][d]);
    /* 1 amu Å per t_ASE for a Cu atom is 1.5458 Å/ps */
    cr_assert_lt(fabs(p->v[5] - 4.6373), 1e-3, "vz %g", p->v[5]);
    particles_destroy(&p);
}

/* Fixed and free boundaries: the same file, other rules per axis. */
Test(readers, lammps_data_boundaries)
{
    char yaml[1024], out[4096];
    const char *data = th_write_temp(2, "m.data", with_line(DATA_OK, 16, "2 1 -0.5 3 3"));
    /* periodic: half an Å below the box is an image (the run wraps it) */
    snprintf(yaml, sizeof yaml, DATA_CASE, data);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
    /* free: within one box length as well */
    snprintf(yaml, sizeof yaml,
             "system:\n  read_data: %s\n  boundary: [free, periodic, periodic]\n"
             "potential: {style: sutton_chen}\n", data);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
    /* fixed: inside [lo, hi] only */
    snprintf(yaml, sizeof yaml,
             "system:\n  read_data: %s\n  boundary: [fixed, periodic, periodic]\n"
             "potential: {style: sutton_chen}\n", data);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 2, "%s", out);
    cr_assert(strstr(out, "m.data:16: atom id 2: x = -0.5 is outside the box [0, 14] (fixed "
                          "boundary along x)"), "%s", out);
    /* free: across the boundary is not a neighbour (0.02 Å apart only
     * through the periodic image along x) */
    data = th_write_temp(2, "m.data", with_line(DATA_OK, 17, "3 1 14.98 1 1"));
    snprintf(yaml, sizeof yaml,
             "system:\n  read_data: %s\n  boundary: [free, periodic, periodic]\n"
             "potential: {style: sutton_chen}\n", data);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
}

/* --- extended XYZ ----------------------------------------------------------- */

#define XYZ_OK                                                                                    \
    "3\nLattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:3:id:I:1 "                \
    "pbc=\"T T T\"\nCu 1 1 1 1\nCu 3 3 3 2\nCu 5 5 5 3\n"
#define XYZ_CASE "system:\n  read_xyz: %s\npotential: {style: sutton_chen}\n"

Test(readers, extxyz_bad_input)
{
    init_long_token();
    char longline[300];
    snprintf(longline, sizeof longline, "Cu 1 %s 1 1", long_token);
    const struct row rows[] = {
        /* a stray second comment line read as an atom: named with file:line */
        {3, "Lattice=\"7.23 0 0 0 7.23 0 0 0 7.23\" Properties=species:S:1:pos:R:3:id:I:1",
         "m.xyz:3: species (column 1): 'Lattice=\"7.23' is not a chemical element symbol "
         "(line 1 says 3 atoms follow the comment line)"},
        {3, "Qq 1 1 1 1", "m.xyz:3: species (column 1): 'Qq' is not a chemical element symbol"},
        /* count line and atom lines disagree */
        {1, "4", "m.xyz:5: file has 3 of the 4 atoms of line 1"},
        {1, "2", "m.xyz:5: 'Cu 5 5 5 3' follows the 2 atoms that line 1 announces; expected the "
                 "end of the file or the count line of a next frame"},
        {1, "3 atoms", "m.xyz:1: first line must be the number of atoms (one integer >= 0)"},
        {1, "30000000", "m.xyz:1: 30000000 atoms are more than the limit of 20000000"},
        /* ids */
        {4, "Cu 3 3 3 1", "m.xyz:4: id: atom id 1 is given twice (also at line 3)"},
        {4, "Cu 3 3 3 2.0", "m.xyz:4: id (column 5): '2.0' is not a positive integer"},
        /* coordinates */
        {4, "Cu 3 3 -10.5 2", "m.xyz:4: atom id 2: z = -10.5 is more than one box length "
                              "outside the box [0, 10) (periodic boundary along z)"},
        {4, "Cu 10.99 1 1.01 2", "m.xyz:4: atom id 2 at (10.99, 1, 1.01) is 0.0141 Å from atom "
                                 "id 1 at line 3"},
        {4, longline, "m.xyz:4: pos (column 3): " LONG_EXCERPT " is not a finite decimal"},
        /* columns and Properties */
        {4, "Cu 3 3 3 2 7", "m.xyz:4: atom line has 6 columns, Properties says 5"},
        {4, "Cu 3 3 2", "m.xyz:4: atom line has 4 columns, Properties says 5"},
        {2, "Lattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:3:id:I:x",
         "m.xyz:2: malformed Properties at 'id'"},
        {2, "Lattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:2:id:I:2",
         "m.xyz:2: Properties: pos must be pos:R:3, found pos:R:2"},
        {2, "Lattice=\"10 0 0 0 10 0 0 0 10 10\" Properties=species:S:1:pos:R:3:id:I:1",
         "m.xyz:2: Lattice needs 9 finite decimal numbers"},
        {2, "Lattice=\"10 0 0 2.5 10 0.5 0 0 10\" Properties=species:S:1:pos:R:3:id:I:1",
         "m.xyz:2: Lattice vector 2 has z component 0.5: the cell must be LAMMPS' restricted "
         "triclinic one"},
        {2, "Lattice=\"10 0 0 0 10 0 0 5.5 10\" Properties=species:S:1:pos:R:3:id:I:1",
         "m.xyz:2: Lattice: tilt yz = 5.5 is more than half the box length ly = 10"},
    };
    run_table("m.xyz", XYZ_OK, XYZ_CASE, rows, sizeof rows / sizeof rows[0]);
}

/* --- EAM: funcfl, setfl, fs --------------------------------------------------- */

#define EAM_CASE(style)                                                                           \
    "system:\n  lattice: {style: fcc, a: 3.615, cells: [2, 2, 2]}\n  element: Cu\n"              \
    "potential:\n  style: " style "\n  file: %s\n  elements: [Cu]\n"

/* 5-point tables, cutoff 3 Å */
#define SETFL_OK                                                                                  \
    "c1\nc2\nc3\n1 Cu\n5 0.01 5 0.75 3.0\n29 63.546 3.615 fcc\n0 -0.1 -0.2 -0.3 -0.4\n"          \
    "0.5 0.4 0.3 0.2 0.1\n1.0 0.5 0.2 0.1 0.0\n"
/* funcfl: 6 points (LAMMPS drops the last one) */
#define FUNCFL_OK                                                                                 \
    "Cu test\n29 63.546 3.615 fcc\n6 0.01 6 0.6 3.0\n0 -0.1 -0.2 -0.3 -0.4 -0.5\n"               \
    "0.5 0.3 0.2 0.1 0.05 0.0\n0.5 0.4 0.3 0.2 0.1 0.0\n"
/* two elements: F, rho(Cu,Cu), rho(Cu,Ag); F, rho(Ag,Cu), rho(Ag,Ag); phi */
#define FS_OK                                                                                     \
    "c1\nc2\nc3\n2 Cu Ag\n5 0.01 5 0.75 3.0\n29 63.546 3.615 fcc\n0 -0.1 -0.2 -0.3 -0.4\n"       \
    "0.5 0.4 0.3 0.2 0.1\n0.5 0.4 0.3 0.2 0.1\n47 107.87 4.09 fcc\n0 -0.1 -0.2 -0.3 -0.4\n"      \
    "0.5 0.4 0.3 0.2 0.1\n0.5 0.4 0.3 0.2 0.1\n1.0 0.5 0.2 0.1 0.0\n1.0 0.5 0.2 0.1 0.0\n"       \
    "1.0 0.5 0.2 0.1 0.0\n"

Test(readers, eam_setfl_bad_input)
{
    init_long_token();
    char longline[300];
    snprintf(longline, sizeof longline, "1.0 0.5 %s 0.1 0.0", long_token);
    const struct row rows[] = {
        {5, "5x 0.01 5 0.75 3.0", "x.eam.alloy:5: expected an integer for Nrho, found '5x'"},
        {5, "5 nan 5 0.75 3.0", "x.eam.alloy:5: expected a number for drho, found 'nan'"},
        {5, "5 0.01 5 0.75 0x3", "x.eam.alloy:5: expected a number for the cutoff, found '0x3'"},
        {6, "29 63.5x 3.615 fcc", "x.eam.alloy:6: expected a number for the mass, found '63.5x'"},
        {7, "0 -0.1 -0.2 1e999 -0.4", "x.eam.alloy:7: expected a number (value 4 of F(rho) of "
                                      "Cu), found '1e999'"},
        {8, "0.5 0.4 0.3abc 0.2 0.1", "x.eam.alloy:8: expected a number (value 3 of rho(r) of "
                                      "Cu), found '0.3abc'"},
        {9, longline, "x.eam.alloy:9: expected a number (value 3 of r*phi(r) of Cu-Cu), found "
                      LONG_EXCERPT},
        {4, "1 CuCuCuCuCuCuCuCuCu", "x.eam.alloy:4: element name 1 'CuCuCuCuCuCuCuCuCu' is "
                                    "longer than 15 characters"},
    };
    run_table("x.eam.alloy", SETFL_OK, EAM_CASE("eam/alloy"), rows, sizeof rows / sizeof rows[0]);
    /* the case key is named as well */
    char yaml[2048], out[4096];
    const char *path = th_write_temp(2, "x.eam.alloy", with_line(SETFL_OK, 5, "5x 0.01 5 0.75 3"));
    snprintf(yaml, sizeof yaml, EAM_CASE("eam/alloy"), path);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 2);
    cr_assert(strstr(out, "bad.yaml:6:9: potential.file: corrupt or unreadable EAM file: "), "%s",
              out);
    /* a Fortran exponent (old DYNAMO files) is a number */
    th_write_temp(2, "x.eam.alloy", with_line(SETFL_OK, 7, "0 -1.0D-01 -0.2 -0.3 -0.4"));
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
}

Test(readers, eam_funcfl_bad_input)
{
    const struct row rows[] = {
        {2, "29.5 63.546 3.615 fcc", "x.eam:2: expected an integer for the atomic number, found "
                                     "'29.5'"},
        {3, "6 0.01 6 0.6 3.0x", "x.eam:3: expected a number for the cutoff, found '3.0x'"},
        {3, "5 0.01 5 0.6 3.0", "x.eam:3: tables need at least 6 points (Nrho = 5, Nr = 5)"},
        {4, "0 -0.1 -0.2 -0.3 inf -0.5", "x.eam:4: expected a number (value 5 of F(rho)), found "
                                         "'inf'"},
        {6, "0.5 0.4 0.3 0.2 0.1x 0", "x.eam:6: expected a number (value 5 of rho(r)), found "
                                      "'0.1x'"},
        {6, "0.5 0.4 0.3", "x.eam:6: unexpected end of file: rho(r) needs 6 values, found 3"},
    };
    run_table("x.eam", FUNCFL_OK, EAM_CASE("eam"), rows, sizeof rows / sizeof rows[0]);
}

Test(readers, eam_fs_bad_input)
{
    const struct row rows[] = {
        {9, "0.5 0.4 0.3 0.2 +-1", "x.eam.fs:9: expected a number (value 5 of rho(r) of Cu), "
                                   "found '+-1'"},
        {10, "47 107.87 4.09e fcc", "x.eam.fs:10: expected a number for the lattice constant, "
                                    "found '4.09e'"},
        {16, "1.0 0.5 0.2 0.1 NaN", "x.eam.fs:16: expected a number (value 5 of r*phi(r) of "
                                    "Ag-Ag), found 'NaN'"},
    };
    run_table("x.eam.fs", FS_OK, EAM_CASE("eam/fs"), rows, sizeof rows / sizeof rows[0]);
}

/* --- Stillinger-Weber ------------------------------------------------------------ */

#define SW_OK                                                                                     \
    "# Si, Stillinger and Weber 1985\nSi Si Si 2.1683 2.0951 1.80 21.0 1.20 -0.333333333333\n"   \
    "  7.049556277 0.6022245584 4.0 0.0 0.0\n"
#define SW_CASE                                                                                   \
    "system:\n  lattice: {style: diamond, a: 5.431, cells: [2, 2, 2]}\n  element: Si\n"          \
    "potential:\n  style: sw\n  file: %s\n  elements: [Si]\n"

Test(readers, sw_bad_input)
{
    init_long_token();
    char longline[300];
    snprintf(longline, sizeof longline, "Si Si Si %.70s 2.0951 1.80 21.0 1.20 -0.3", long_token);
    const struct row rows[] = {
        {2, "Si Si Si 2.1683 2.0951x 1.80 21.0 1.20 -0.333333333333",
         "x.sw:2: field 5 (sigma): '2.0951x' is not a finite decimal number"},
        {2, "Si Si Si 2.1683 -2 1.80 21.0 1.20 -0.333333333333",
         "x.sw:2: field 5 (sigma) must be >= 0, found -2"},
        /* sigma 0 is legal (GaN.sw's mixed entries), but a potential
         * whose only pair has no range is not */
        {2, "Si Si Si 2.1683 0 1.80 21.0 1.20 -0.333333333333",
         "no pair of the elements in use interacts (a * sigma is 0 in every i j j entry)"},
        {2, "Si Si Si 2.1683 2.0951 1.80 -21.0 1.20 -0.333333333333",
         "x.sw:2: field 7 (lambda) must be >= 0, found -21"},
        {3, "  nan 0.6022245584 4.0 0.0 0.0", "x.sw:3: field 10 (A): 'nan' is not a finite "
                                               "decimal number"},
        {3, "  7.049556277 0.6022245584 4.0 0.0", "x.sw:3: incomplete Stillinger-Weber entry: 14 "
                                                  "fields needed, 13 found"},
        {3, "  7.049556277 0.6022245584 4.0 0.0 0.0\n"
            "Si Si Si 2.1683 2.0951 1.80 21.0 1.20 -0.333333333333\n"
            "  7.049556277 0.6022245584 4.0 0.0 0.0",
         "x.sw:4: second entry for Si Si Si (the first is at line 2)"},
        {2, longline, "x.sw:2: field 4 (epsilon): '1xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx...' "
                      "is longer than 63 characters"},
    };
    run_table("x.sw", SW_OK, SW_CASE, rows, sizeof rows / sizeof rows[0]);
}

/* --- meam/spline ------------------------------------------------------------------ */

/* The refusals below come before anything of the size asked for is
 * built; before they existed, building it kept `check` busy past 60 s or
 * ran out of memory.  10 s tells the two apart on any machine: the
 * refusals took up to 1.04 s under AddressSanitizer at a load of 6-10 on
 * two cores (a 1 s bound failed there), 0.01-0.1 s on an idle machine. */
#define REFUSAL_SECONDS_MAX 10.0

#define MEAM_CASE                                                                                 \
    "system:\n  lattice: {style: diamond, a: 5.431, cells: [2, 2, 2]}\n  element: Si\n"          \
    "potential:\n  style: meam/spline\n  file: %s\n  elements: [Si]\n"

Test(readers, meam_spline_bad_input)
{
    /* Debian's Si_1.meam.spline (old format): line 2 is phi's knot count
     * (10), 3 its end slopes, 4 ignored, 5..14 its knots */
    FILE *f = fopen("/usr/share/lammps/potentials/Si_1.meam.spline", "r");
    cr_assert_not_null(f, "lammps-data's Si_1.meam.spline is needed");
    static char text[32768];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    const struct row rows[] = {
        {2, "10x", "x.meam.spline:2: expected an integer for the knot count of spline phi, found "
                   "'10x'"},
        {3, "-4.266966781858503300e+01 nan", "x.meam.spline:3: expected a number (value 2 of the "
                                             "end slopes of spline phi), found 'nan'"},
        {5, "0x1p1 6.929943430771341000e+00 1.653321602557917600e+02",
         "x.meam.spline:5: expected a number (value 1 of knot 1 of spline phi), found '0x1p1'"},
        {6, "1.4 -4.399503747408950400e-01 3.941543472528634600e+01",
         "x.meam.spline:14: spline phi: knots must increase (knot 2 at 1.4 after 1.5)"},
    };
    run_table("x.meam.spline", text, MEAM_CASE, rows, sizeof rows / sizeof rows[0]);
}

/* --- dpd_fit points CSV ----------------------------------------------------------------- */

#define CSV_OK                                                                                    \
    "# test isotherm\nlattice_constant_A,density_g_cm3,pressure_GPa\n3.40,10.74,47.33\n"          \
    "3.50,9.84,20.57\n3.60,9.05,4.26\n3.70,8.33,-1.5\n3.80,7.70,-5.2\n"
#define CSV_CASE                                                                                  \
    "type: dpd_fit\nisotherm: {temperature: 298, points_file: %s}\n"                              \
    "coarse_grain: {a: 7.23, cutoff: 10.845}\noutput_file: fitted.yaml\n"

Test(readers, dpd_fit_points_csv_bad_input)
{
    const struct row rows[] = {
        {3, "3.40,10.7x,47.33", "iso.csv:3: column 2: '10.7x' is not a finite decimal number"},
        {3, "3.40,,47.33", "iso.csv:3: empty column"},
        {3, "3.40,10.74,47.33,", "iso.csv:3: empty column"},
        {3, "3.40,10.74,47.33,1", "iso.csv:3: more columns than the 3 of the header"},
        {3, "3.40,10.74", "iso.csv:3: 2 columns, the header has 3"},
    };
    run_table("iso.csv", CSV_OK, CSV_CASE, rows, sizeof rows / sizeof rows[0]);
}

/* --- limits: particle count and interaction range ---------------------------------------- */

/* 4e15 atoms: refused by resolve (--key) and check before any is made. */
Test(limits, huge_lattice_refused_quickly)
{
    static const struct {
        const char *yaml;
        const char *expect;
    } cases[] = {
        {"system:\n  lattice: {style: fcc, a: 3.615, cells: [100000, 100000, 100000]}\n"
         "  element: Cu\npotential: {style: sutton_chen}\n",
         "bad.yaml:2:42: system.lattice.cells: 100000 x 100000 x 100000 cells of 4 sites are "
         "4e+15 atoms, more than system.max_particles = 20000000 (the default; set it to allow "
         "more)"},
        {"type: hugoniot\nhugoniot:\n  element: Cu\n  a: 3.615\n  cells: [100000, 100000, 100000]\n"
         "  particle_velocities: [1.0]\npotential: {style: sutton_chen}\n",
         "bad.yaml:5:10: hugoniot.cells: 100000 x 100000 x 100000 cells of 4 atoms are 4e+15 "
         "atoms, more than hugoniot.max_particles = 20000000"},
        {"type: cluster_impact\ntarget:\n  element: Cu\n  a: 3.615\n  cells: [10000, 10000, 10000]\n"
         "cluster: {atoms: 14}\npotential: {style: sutton_chen}\n",
         "bad.yaml:5:10: target.cells: 10000 x 10000 x 10000 cells of 4 sites and a cluster of 14 "
         "are 4e+12 atoms, more than target.max_particles = 20000000"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char out[4096];
        double secs;
        int rc = solver("check", cases[k].yaml, NULL, out, sizeof out, &secs);
        cr_assert_eq(rc, 2, "check %zu: %s", k, out);
        cr_assert(strstr(out, cases[k].expect), "check %zu:\n  expected: %s\n  got: %s", k,
                  cases[k].expect, out);
        cr_assert_lt(secs, REFUSAL_SECONDS_MAX, "check %zu took %.2f s", k, secs);
        rc = solver("resolve", cases[k].yaml, "--key", out, sizeof out, &secs);
        cr_assert_eq(rc, 2, "resolve --key %zu: %s", k, out);
        cr_assert(strstr(out, cases[k].expect), "resolve %zu:\n  expected: %s\n  got: %s", k,
                  cases[k].expect, out);
        cr_assert_lt(secs, REFUSAL_SECONDS_MAX, "resolve %zu took %.2f s", k, secs);
    }
}

/* system.max_particles: the limit is the case's, for the atoms and,
 * separately, for their periodic images; the key appears in the resolved
 * case only when given (job keys of other cases do not move). */
Test(limits, max_particles_is_the_cases_limit)
{
    char out[16384];
    const char *base = "system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n"
                       "  element: Cu\n%s"
                       "potential: {style: sutton_chen}\n";
    char yaml[1024];
    snprintf(yaml, sizeof yaml, base, "  max_particles: 107\n");
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 2, "%s", out);
    cr_assert(strstr(out, "system.lattice.cells: 3 x 3 x 3 cells of 4 sites are 108 atoms, "
                          "more than system.max_particles = 107\n"), "%s", out);
    /* 108 atoms in a 10.8 Å box have about 3370 images within the
     * Sutton-Chen cutoff plus skin (11.8 Å) */
    snprintf(yaml, sizeof yaml, base, "  max_particles: 3000\n");
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 2, "%s", out);
    cr_assert(strstr(out, "needs about 3.37e+03 ghost atoms (periodic images), more than "
                          "system.max_particles = 3000\n"), "%s", out);
    snprintf(yaml, sizeof yaml, base, "  max_particles: 5000\n");
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
    cr_assert_eq(solver("resolve", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
    cr_assert(strstr(out, "\"max_particles\":5000"), "%s", out);
    snprintf(yaml, sizeof yaml, base, "");
    cr_assert_eq(solver("resolve", yaml, NULL, out, sizeof out, NULL), 0, "%s", out);
    cr_assert_null(strstr(out, "max_particles"), "default written into the case: %s", out);
    snprintf(yaml, sizeof yaml, base, "  max_particles: 0\n");
    cr_assert_eq(solver("resolve", yaml, NULL, out, sizeof out, NULL), 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:4:18: system.max_particles: must be in [1, 1e+09] (got 0)"),
              "%s", out);
    /* a data file's count against it */
    const char *data = th_write_temp(2, "m.data", DATA_OK);
    snprintf(yaml, sizeof yaml,
             "system:\n  read_data: %s\n  max_particles: 2\npotential: {style: sutton_chen}\n",
             data);
    cr_assert_eq(solver("check", yaml, NULL, out, sizeof out, NULL), 2, "%s", out);
    cr_assert(strstr(out, "m.data:3: 3 atoms are more than the limit of 2 "
                          "(system.max_particles)"), "%s", out);
}

/* A Stillinger-Weber sigma of 2999999999 Å (cutoff 5.4e9 Å in a 10.9 Å
 * box) kept check busy past 60 s building image layers; now the range is
 * refused before any ghost is made, naming the case key and the line of
 * the file.  The same for a cutoff or skin from the case. */
Test(limits, huge_cutoff_refused_quickly)
{
    const char *sw = th_write_temp(2, "big.sw",
                                   "Si Si Si 2.1683 2999999999 1.80 21.0 1.20 -0.333333333333\n"
                                   "  7.049556277 0.6022245584 4.0 0.0 0.0\n");
    char yaml[1024], out[4096];
    snprintf(yaml, sizeof yaml, SW_CASE, sw);
    double secs;
    int rc = solver("check", yaml, NULL, out, sizeof out, &secs);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:6:9: potential.file: cutoff 5.4e+09 Å (from ") &&
                  strstr(out, "big.sw:1 (a * sigma of Si Si Si)) plus skin 1 Å against the "
                              "10.862 x 10.862 x 10.862 Å box (periodic periodic periodic) needs "
                              "about ") &&
                  strstr(out, "ghost atoms (periodic images), more than system.max_particles = "
                              "20000000"),
              "%s", out);
    cr_assert_lt(secs, REFUSAL_SECONDS_MAX, "check took %.2f s", secs);
    static const struct {
        const char *yaml;
        const char *expect;
    } cases[] = {
        {"system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n  element: Cu\n"
         "potential: {style: lj, elements: [Cu], epsilon: [0.4], sigma: [2.3], cutoff: 1e5}\n",
         "bad.yaml:4:78: potential.cutoff: cutoff 100000 Å plus skin 1 Å against the 10.845 x "
         "10.845 x 10.845 Å box"},
        {"system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n  element: Cu\n"
         "potential: {style: sutton_chen}\nmd: {skin: 1e6}\n",
         "bad.yaml:5:12: md.skin: cutoff 10.83 Å plus skin 1e+06 Å"},
        /* free boundaries: no images, but a list of every pair (of
         * 70304 atoms: 2.47e9 pairs, just past INT_MAX) */
        {"system:\n  lattice: {style: fcc, a: 3.615, cells: [26, 26, 26]}\n  element: Cu\n"
         "  boundary: [free, free, free]\n"
         "potential: {style: lj, elements: [Cu], epsilon: [0.4], sigma: [2.3], cutoff: 1e4}\n",
         "bad.yaml:5:78: potential.cutoff: cutoff 10000 Å plus skin 1 Å: the neighbour list of "
         "70304 atoms would hold about 2.47e+09 entries"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        rc = solver("check", cases[k].yaml, NULL, out, sizeof out, &secs);
        cr_assert_eq(rc, 2, "%zu: %s", k, out);
        cr_assert(strstr(out, cases[k].expect), "%zu:\n  expected: %s\n  got: %s", k,
                  cases[k].expect, out);
        cr_assert_lt(secs, REFUSAL_SECONDS_MAX, "%zu took %.2f s", k, secs);
    }
}

/* The crystal and elastic case types build their crystals when they run: the
 * same range rule at `check`, naming the key, for the smallest crystal
 * (cells of a_min). */
Test(limits, crystal_cases_check_the_range)
{
    static const struct {
        const char *yaml;
        const char *expect;
    } cases[] = {
        {"type: crystal\ncrystal: {lattice: fcc, element: Cu, a_min: 3.4, a_max: 3.8, cells: 3}\n"
         "potential: {style: lj, elements: [Cu], epsilon: [0.4], sigma: [2.3], cutoff: 5000}\n",
         "bad.yaml:3:78: potential.cutoff: cutoff 5000 Å plus skin 0.5 Å against the 10.2 x 10.2 "
         "x 10.2 Å box (periodic periodic periodic) needs about 1.02e+11 ghost atoms (periodic "
         "images), more than the solver's particle limit = 20000000 (the 3 x 3 x 3 crystal at "
         "a = 3.4 Å)"},
        {"type: elastic\ncrystal: {lattice: fcc, element: Cu, a_min: 3.5, a_max: 3.7, cells: 2}\n"
         "potential: {style: lj, elements: [Cu], epsilon: [0.4], sigma: [2.3], cutoff: 60}\n",
         "bad.yaml:3:78: potential.cutoff: cutoff 60 Å plus skin 1 Å: the neighbour list of 32 "
         "atoms would hold about"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char out[4096];
        double secs;
        int rc = solver("check", cases[k].yaml, NULL, out, sizeof out, &secs);
        cr_assert_eq(rc, 2, "%zu: %s", k, out);
        cr_assert(strstr(out, cases[k].expect), "%zu:\n  expected: %s\n  got: %s", k,
                  cases[k].expect, out);
        cr_assert_lt(secs, REFUSAL_SECONDS_MAX, "%zu took %.2f s", k, secs);
    }
    /* a sane cutoff passes */
    char out[4096];
    int rc = solver("check",
                    "type: crystal\ncrystal: {lattice: fcc, element: Cu, a_min: 3.4, a_max: 3.8, "
                    "cells: 3}\npotential: {style: sutton_chen}\n",
                    NULL, out, sizeof out, NULL);
    cr_assert_eq(rc, 0, "%s", out);
}
