/*
 * A data or XYZ file on bricks (input/md_system.c, core/halo_scatter.h):
 * under `mpirun -np N` (N > 1) only rank 0 reads and checks the file,
 * applies the region and the displacement as a serial run does, and sends
 * the atoms to their owners in blocks.  The runs on 1 (bricks asked for),
 * 2 and 4 ranks agree with the serial run as the other brick tests do
 * (thermo series to 1e-10 of each column's largest magnitude over 100
 * steps, metrics to 1e-10 relative), the set-up's positions bitwise; a
 * replicated run gets every atom and is the serial run bitwise; a bad
 * file stops every rank with rank 0's message (file:line and field) and
 * the serial exit code, without a hang; and the other ranks' peak memory
 * no longer holds the file.
 */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10

static const char *const series_cols[] = {"pe_eV",   "ke_eV",   "etotal_eV", "temp_K",
                                          "press_GPa", "pxx_GPa", "pyy_GPa",   "pzz_GPa",
                                          "pxy_GPa", "pxz_GPa", "pyz_GPa",   NULL};

/* next of a small LCG, as a uniform in [-1, 1) */
static double lcg(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((double)(*s >> 8) / (double)(1u << 24) - 0.5) * 2.0;
}

/* A LAMMPS data file of n^3 fcc Cu cells (lattice constant a), positions
 * jittered by up to 0.05 Å, velocities up to vmax Å/ps, the ids a
 * permutation of the file order (k -> 7k mod N + 1), every 10th atom
 * written one box length along +x with image flag -1 (the run wraps it
 * back).  dup_at > 0: the atom written dup_at-th repeats the id of the
 * one before it.  Returns the atom count; the text goes to buf. */
static long cu_data(char *buf, size_t len, int n, double a, double vmax, long dup_at)
{
    const double L = n * a;
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    long N = 4L * n * n * n;
    size_t at = (size_t)snprintf(buf, len,
                                 "test file\n\n%ld atoms\n1 atom types\n\n0 %.10g xlo xhi\n"
                                 "0 %.10g ylo yhi\n0 %.10g zlo zhi\n\nMasses\n\n1 63.546\n\n"
                                 "Atoms # atomic\n\n",
                                 N, L, L, L);
    unsigned s = 4242;
    long k = 0, prev = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int l = 0; l < n; l++)
                for (int b = 0; b < 4; b++, k++) {
                    double x[3] = {(i + basis[b][0]) * a, (j + basis[b][1]) * a,
                                   (l + basis[b][2]) * a};
                    for (int d = 0; d < 3; d++)
                        x[d] += 0.05 * lcg(&s);
                    int ix = 0;
                    if (k % 10 == 3) {
                        x[0] += L;
                        ix = -1;
                    }
                    long id = (7 * k) % N + 1;   /* 7 is prime to 864 and 108000 */
                    if (k + 1 == dup_at)
                        id = prev;
                    prev = id;
                    at += (size_t)snprintf(buf + at, len - at, "%ld 1 %.12g %.12g %.12g %d 0 0\n",
                                           id, x[0], x[1], x[2], ix);
                    cr_assert_lt(at, len, "data file buffer too small");
                }
    at += (size_t)snprintf(buf + at, len - at, "\nVelocities\n\n");
    for (k = 0; k < N; k++) {
        double v[3];
        for (int d = 0; d < 3; d++)
            v[d] = vmax * lcg(&s);
        at += (size_t)snprintf(buf + at, len - at, "%ld %.12g %.12g %.12g\n", k + 1, v[0], v[1],
                               v[2]);
        cr_assert_lt(at, len, "data file buffer too small");
    }
    return N;
}

/* An extended XYZ file of 4^3 diamond Si cells (a = 5.431 Å, 512 atoms),
 * jittered by up to 0.03 Å, with an id column (the file order reversed).
 * bad_line > 0: that line (1-based, an atom line) gets a malformed
 * coordinate. */
static void si_xyz(char *buf, size_t len, long bad_line)
{
    const int n = 4;
    const double a = 5.431, L = n * a;
    static const double basis[8][3] = {{0, 0, 0},          {0.5, 0.5, 0},      {0.5, 0, 0.5},
                                       {0, 0.5, 0.5},      {0.25, 0.25, 0.25}, {0.75, 0.75, 0.25},
                                       {0.75, 0.25, 0.75}, {0.25, 0.75, 0.75}};
    long N = 8L * n * n * n;
    size_t at = (size_t)snprintf(buf, len,
                                 "%ld\nLattice=\"%.10g 0 0 0 %.10g 0 0 0 %.10g\" "
                                 "Properties=species:S:1:pos:R:3:id:I:1 pbc=\"T T T\"\n",
                                 N, L, L, L);
    unsigned s = 99;
    long k = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int l = 0; l < n; l++)
                for (int b = 0; b < 8; b++, k++) {
                    double x[3] = {(i + basis[b][0]) * a, (j + basis[b][1]) * a,
                                   (l + basis[b][2]) * a};
                    for (int d = 0; d < 3; d++)
                        x[d] += 0.03 * lcg(&s);
                    if (k + 3 == bad_line)
                        at += (size_t)snprintf(buf + at, len - at, "Si %.12g %.12gx %.12g %ld\n",
                                               x[0], x[1], x[2], N - k);
                    else
                        at += (size_t)snprintf(buf + at, len - at, "Si %.12g %.12g %.12g %ld\n",
                                               x[0], x[1], x[2], N - k);
                    cr_assert_lt(at, len, "xyz buffer too small");
                }
}

static const char *const md_metrics[] = {"atoms", "pe", "ke", "etotal", "temperature",
                                         "pressure", "pxx", "pyy", "pzz", "max_force",
                                         "volume", NULL};
static const char *const dpd_series[] = {"pe_eV", "ke_eV", "etotal_eV", "temp_K", "press_GPa",
                                         NULL};
static const char *const dpd_metrics[] = {"particles", "pe", "ke", "etotal", "temperature",
                                          "temperature_mean", "pressure_mean",
                                          "neighbor_rebuilds", NULL};

/* What a case type's runs are compared on: thermo columns and metrics. */
struct what {
    const char *const *series, *const *metrics;
    const char *count;   /* the metric counting the particles */
};
static const struct what md_what = {series_cols, md_metrics, "atoms"};
static const struct what dpd_what = {dpd_series, dpd_metrics, "particles"};

/* The thermo series over at least 11 rows and the final metrics. */
static void compare_runs(const char *a, const char *b, const struct what *w, const char *tag)
{
    long n;
    free(thb_read_h5(a, "/series/pe_eV", H5T_NATIVE_DOUBLE, sizeof(double), &n));
    cr_assert_geq(n, 11, "%s: %ld thermo rows", tag, n);
    thb_compare_series(a, b, w->series, REL, tag);
    thb_compare_metrics(a, b, w->metrics, REL, tag);
}

/* The set-up (snapshot of step 0): the same ids; positions bitwise (the
 * displacement and the wrap are the serial ones); velocities to vrel of
 * their largest magnitude (0: bitwise, the file's). */
static void compare_setup(const char *a, const char *b, double vrel, const char *tag)
{
    thb_compare_setup(a, b, 0.1, vrel, tag);
}

/* The case (body: its text after `system:` with %s for the file) serially,
 * on 1 rank with decomposition: bricks and on 2 and 4 ranks under auto,
 * each against the serial run. */
static void matches_serial(const char *stem, const char *file, const char *body, long natoms,
                           double vrel, const struct what *w)
{
    char yaml[2048], yaml1[2100], name[64], name1[64], d0[600], dk[600], tag[96];
    snprintf(yaml, sizeof yaml, body, file);
    snprintf(yaml1, sizeof yaml1, "%sparallel: {decomposition: bricks}\n", yaml);
    snprintf(name, sizeof name, "%s.yaml", stem);
    snprintf(name1, sizeof name1, "%s-bricks.yaml", stem);
    const char *path = th_write_temp(2, name, yaml);
    const char *path1 = th_write_temp(3, name1, yaml1);
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), stem);
    thb_must_run(path, 0, d0, NULL);
    json_t *r0 = thb_result(d0);
    cr_assert_eq((long)thb_metric(r0, w->count), natoms, "%s: serial count", stem);
    json_decref(r0);
    const int nps[3] = {1, 2, 4};
    for (int k = 0; k < 3; k++) {
        snprintf(dk, sizeof dk, "%s/%s-%d", th_temp_dir(), stem, nps[k]);
        snprintf(tag, sizeof tag, "%s on %d ranks", stem, nps[k]);
        if (nps[k] == 1) {
            thb_must_run(path1, 1, dk, NULL);
            thb_assert_bricks(dk, 1, NULL);
        } else {
            thb_must_run_auto_bricks(path, nps[k], dk);
        }
        compare_setup(d0, dk, vrel, tag);
        compare_runs(d0, dk, w, tag);
        thb_check_parallel_record(dk, nps[k], natoms);
    }
}

/* EAM Cu from a data file: velocities and image flags from the file, a
 * slab region and a displacement (the k-th displacement to the k-th atom
 * the region keeps, in the file's order, as serially) */
Test(bricks_read, read_data_matches_serial, .timeout = 900)
{
    static char text[1 << 18];
    long n = cu_data(text, sizeof text, 6, 3.615, 3.0, 0);
    cr_assert_eq(n, 864);
    const char *file = th_write_temp(0, "cu.data", text);
    /* the slab keeps the atoms of 5 of the 6 cell layers along z (the
     * jitter is smaller than the planes' distance to its faces) */
    matches_serial("rd", file,
                   "seed: 13\nsystem:\n  read_data: %s\n  elements: [Cu]\n  displace: 0.03\n"
                   "  region: {shape: slab, axis: z, lo: -0.9, hi: 16.9}\n"
                   "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                   "md: {steps: 100, temperature: 0}\noutput: {thermo_every: 10}\n",
                   720, 0.0, &md_what);
}

/* Stillinger-Weber Si (full lists) from an extended XYZ file with an id
 * column in reverse order, a displacement and Maxwell velocities (drawn
 * by id over all ranks: to round-off) */
Test(bricks_read, read_xyz_matches_serial, .timeout = 900)
{
    static char text[1 << 16];
    si_xyz(text, sizeof text, 0);
    const char *file = th_write_temp(0, "si.xyz", text);
    matches_serial("rx", file,
                   "seed: 17\nsystem:\n  read_xyz: %s\n  displace: 0.02\n"
                   "potential: {style: sw, file: Si.sw, elements: [Si]}\n"
                   "md: {steps: 100, temperature: 600}\noutput: {thermo_every: 10}\n",
                   512, 1e-13, &md_what);
}

/* DPD (`type: dpd`) from a data file: coarse-grained Cu particles (6^3
 * fcc cells of 7.28 Å, 864 particles), the file's velocities, the cell
 * sweep (the serial run's order on every rank count, tests/test_bricks_dpd.c) */
Test(bricks_read, dpd_read_data_matches_serial, .timeout = 900)
{
    static char text[1 << 18];
    cu_data(text, sizeof text, 6, 7.28, 0.5, 0);
    const char *file = th_write_temp(0, "cg.data", text);
    th_write_temp(1, "cg.yaml",
                  "element: Cu\nepsilon: 0.1\nc: 39.0\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"
                  "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.23\n");
    matches_serial("dpd", file,
                   "type: dpd\nseed: 5\nsystem:\n  read_data: %s\n  elements: [Cu]\n"
                   "dpd: {parameters: cg.yaml, gamma: 2.0, steps: 100, timestep: 0.01, "
                   "sweep: cells}\noutput: {thermo_every: 10, snapshot_every: 100}\n",
                   864, 0.0, &dpd_what);
}

/* decomposition: replicated: rank 0 reads, every rank receives every atom
 * (in blocks), and the run is the serial one bitwise */
Test(bricks_read, replicated_read_is_the_serial_run, .timeout = 600)
{
    static char text[1 << 18], ta[1 << 16], tb[1 << 16];
    cu_data(text, sizeof text, 6, 3.615, 3.0, 0);
    const char *file = th_write_temp(0, "cu.data", text);
    char yaml[1024], d0[600], d2[600];
    snprintf(yaml, sizeof yaml,
             "seed: 13\nsystem:\n  read_data: %s\n  elements: [Cu]\n  displace: 0.03\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 50, temperature: 0}\noutput: {thermo_every: 10}\n"
             "parallel: {decomposition: replicated}\n",
             file);
    const char *path = th_write_temp(1, "repl.yaml", yaml);
    snprintf(d0, sizeof d0, "%s/repl-serial", th_temp_dir());
    snprintf(d2, sizeof d2, "%s/repl-2", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 2, d2, NULL);
    thb_read_text(d0, "thermo.csv", ta, sizeof ta);
    thb_read_text(d2, "thermo.csv", tb, sizeof tb);
    const char *xa = strchr(ta, '\n'), *xb = strchr(tb, '\n');
    cr_assert(xa && xb && strlen(xa) > 200, "thermo.csv too short");
    cr_assert_str_eq(xa, xb, "replicated thermo.csv differs from the serial one");
    json_t *r = thb_result(d2);
    cr_assert_eq((long)thb_metric(r, "atoms"), 864);
    json_decref(r);
}

/* Run the case at path under `timeout` (a hang fails the test as exit 124)
 * on np ranks (0: serially) with stdout dropped; stderr into err. */
static int run_stderr(const char *path, int np, const char *dir, char *err, size_t len)
{
    thb_mpi_env(np);
    char cmd[2048];
    if (np > 0)
        snprintf(cmd, sizeof cmd,
                 "timeout 300 /usr/bin/mpirun -np %d --oversubscribe %s run %s --out %s --quiet "
                 ">/dev/null",
                 np, th_solver(), path, dir);
    else
        snprintf(cmd, sizeof cmd, "timeout 300 %s run %s --out %s --quiet >/dev/null",
                 th_solver(), path, dir);
    const char *argv[] = {"/bin/sh", "-c", cmd, NULL};
    return th_run(argv, err, len);
}

/* The serial run's `error: ...` line (asserting it failed with want_rc),
 * then the same case on np ranks: the same exit code, that line exactly
 * once on stderr, no other rank's message, no hang. */
static void fails_alike(const char *yaml_path, const char *stem, int np, int want_rc,
                        const char *must_name)
{
    static char err0[16384], errn[16384];
    char d0[600], dn[600];
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), stem);
    snprintf(dn, sizeof dn, "%s/%s-%d", th_temp_dir(), stem, np);
    int rc0 = run_stderr(yaml_path, 0, d0, err0, sizeof err0);
    cr_assert_eq(rc0, want_rc, "%s serially: exit %d\n%s", stem, rc0, err0);
    char *line = strstr(err0, "error: ");
    cr_assert_not_null(line, "%s: no error line\n%s", stem, err0);
    char *nl = strchr(line, '\n');
    if (nl)
        *nl = '\0';
    cr_assert_not_null(strstr(line, must_name), "%s: '%s' does not name %s", stem, line,
                       must_name);
    int rcn = run_stderr(yaml_path, np, dn, errn, sizeof errn);
    cr_assert_neq(rcn, 124, "%s on %d ranks: hung (timeout)\n%s", stem, np, errn);
    cr_assert_eq(rcn, want_rc, "%s on %d ranks: exit %d, serially %d\n%s", stem, np, rcn, rc0,
                 errn);
    char *first = strstr(errn, line);
    cr_assert_not_null(first, "%s on %d ranks: no '%s' on stderr\n%s", stem, np, line, errn);
    cr_assert_null(strstr(first + 1, line), "%s on %d ranks: the message twice\n%s", stem, np,
                   errn);
    cr_assert_null(strstr(errn, "error: rank "), "%s on %d ranks: another rank's message\n%s",
                   stem, np, errn);
}

/* A duplicate atom id (data file, 2 ranks), a malformed coordinate (XYZ,
 * 4 ranks) and a missing file (2 ranks): every rank stops with rank 0's
 * message naming the file and line, and the serial exit code (2) */
Test(bricks_read, bad_file_fails_on_every_rank, .timeout = 900)
{
    static char text[1 << 18];
    char yaml[1024], want[700];
    cu_data(text, sizeof text, 6, 3.615, 3.0, 100);   /* the 100th atom line repeats the 99th's id */
    const char *data = th_write_temp(0, "dup.data", text);
    snprintf(yaml, sizeof yaml,
             "seed: 1\nsystem:\n  read_data: %s\n  elements: [Cu]\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 10}\n",
             data);
    const char *path = th_write_temp(1, "dup.yaml", yaml);
    /* the Atoms section starts at line 16: the 100th atom is on line 115 */
    snprintf(want, sizeof want, "%s:115: Atoms: atom id", data);
    fails_alike(path, "dup", 2, 2, want);

    si_xyz(text, sizeof text, 40);
    const char *xyz = th_write_temp(2, "bad.xyz", text);
    snprintf(yaml, sizeof yaml,
             "seed: 1\nsystem:\n  read_xyz: %s\n"
             "potential: {style: sw, file: Si.sw, elements: [Si]}\nmd: {steps: 10}\n",
             xyz);
    path = th_write_temp(3, "badxyz.yaml", yaml);
    snprintf(want, sizeof want, "%s:40:", xyz);
    fails_alike(path, "badxyz", 4, 2, want);

    snprintf(yaml, sizeof yaml,
             "seed: 1\nsystem:\n  read_data: %s/no-such.data\n  elements: [Cu]\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 10}\n",
             th_temp_dir());
    path = th_write_temp(4, "missing.yaml", yaml);
    snprintf(want, sizeof want, "missing.yaml:3:");
    fails_alike(path, "missing", 2, 2, want);
}

/* Peak memory: a data file of 108,000 atoms (30^3 fcc cells) of which a
 * sphere region keeps about 1200: rank 0 reads the whole file, the other
 * ranks only ever receive their few hundred atoms, so their peak RSS
 * (result.json's parallel.peak_rss_mib_per_rank) stays well below rank
 * 0's.  When every rank read the file whole all four peaks were within
 * 0.3 MiB of each other (45.6-45.8 MiB, default build); now the others
 * are about 20 MiB lower (92 MiB in the sanitizer build): the bound is 10
 * MiB (the particle arrays of 108,000 atoms alone are 17.7 MiB). */
Test(bricks_read, other_ranks_never_hold_the_file, .timeout = 900)
{
    size_t len = (size_t)64 << 20;
    char *text = malloc(len);
    cr_assert_not_null(text);
    long n = cu_data(text, len, 30, 3.615, 3.0, 0);
    cr_assert_eq(n, 108000);
    const char *file = th_write_temp(0, "big.data", text);
    free(text);
    char yaml[1024], dir[600];
    snprintf(yaml, sizeof yaml,
             "seed: 1\nsystem:\n  read_data: %s\n  elements: [Cu]\n"
             "  region: {shape: sphere, center: [54.225, 54.225, 54.225], radius: 15}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 0}\noutput: {hdf5: false}\n",
             file);
    const char *path = th_write_temp(1, "big.yaml", yaml);
    snprintf(dir, sizeof dir, "%s/big-4", th_temp_dir());
    thb_must_run_auto_bricks(path, 4, dir);
    json_t *r = thb_result(dir);
    long atoms = (long)thb_metric(r, "atoms");
    cr_assert(atoms > 1000 && atoms < 1500, "the sphere keeps %ld atoms", atoms);
    json_t *rss = json_object_get(json_object_get(r, "parallel"), "peak_rss_mib_per_rank");
    cr_assert_eq(json_array_size(rss), 4);
    double root = json_number_value(json_array_get(rss, 0)), other = 0;
    for (size_t k = 1; k < 4; k++)
        other = fmax(other, json_number_value(json_array_get(rss, k)));
    cr_log_info("108,000-atom file, 4 ranks: peak RSS rank 0 %.1f MiB, others at most %.1f MiB",
                root, other);
    cr_assert_lt(other, root - 10.0,
                 "peak RSS of rank 0 %.1f MiB, of another rank %.1f MiB: the file's atoms seem "
                 "to be on every rank", root, other);
    json_decref(r);
}
