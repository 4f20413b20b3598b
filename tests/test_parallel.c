/*
 * Replicated-data MPI runs (`parallel: {decomposition: replicated}`):
 * `mpirun -np 2 cascade-solver run` gives the same trajectory as a serial
 * run (bitwise on this machine: sums are reduced to rank 0 and broadcast),
 * and only rank 0 writes files.  Brick decompositions: test_bricks.c.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

static void read_file(const char *path, char *buf, size_t len)
{
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s missing", path);
    size_t n = fread(buf, 1, len - 1, f);
    buf[n] = '\0';
    fclose(f);
}

/* Runs the case serially and on 2 ranks; the thermo tables must agree. */
static void check_two_ranks(const char *tag, const char *yaml)
{
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMP_NUM_THREADS", "1", 1);
    char name[64];
    snprintf(name, sizeof name, "%s.yaml", tag);
    const char *path = th_write_temp(6, name, yaml);
    char d1[512], d2[512], out[8192];
    snprintf(d1, sizeof d1, "%s/%s-serial", th_temp_dir(), tag);
    snprintf(d2, sizeof d2, "%s/%s-mpi", th_temp_dir(), tag);
    const char *a1[] = {th_solver(), "run", path, "--out", d1, "--quiet", NULL};
    cr_assert_eq(th_run(a1, out, sizeof out), 0, "%s", out);
    /* Open MPI's dlopen'ed components leak at exit and cannot be named in
     * a suppression (their modules are unloaded); the serial runs keep leak
     * checking for our code */
    setenv("ASAN_OPTIONS", "detect_leaks=0", 1);
    const char *a2[] = {"/usr/bin/mpirun", "-np", "2", "--oversubscribe", th_solver(), "run", path,
                        "--out", d2, "--quiet", NULL};
    cr_assert_eq(th_run(a2, out, sizeof out), 0, "%s", out);
    static char t1[65536], t2[65536];
    char p1[600], p2[600];
    snprintf(p1, sizeof p1, "%s/thermo.csv", d1);
    snprintf(p2, sizeof p2, "%s/thermo.csv", d2);
    read_file(p1, t1, sizeof t1);
    read_file(p2, t2, sizeof t2);
    cr_assert(strlen(t1) > 100);
    cr_assert_str_eq(t1, t2, "%s: thermo differs:\n%s\nvs\n%s", tag, t1, t2);
}

Test(parallel, two_ranks_match_serial, .timeout = 300)
{
    check_two_ranks("eam", "seed: 3\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [5, 5, 5]}\n"
                           "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                           "md: {steps: 60, temperature: 400}\n"
                           "parallel: {decomposition: replicated}\n"
                           "output: {thermo_every: 20, hdf5: false}\n");
}

/* Many-body potentials with full lists: every rank needs the embedding
 * derivatives of the other ranks' atoms (meam/spline) or only its own
 * triplets (sw). */
Test(parallel, two_ranks_match_serial_silicon, .timeout = 300)
{
    check_two_ranks("sw", "seed: 4\nsystem:\n  lattice: {style: diamond, a: 5.431, cells: [3, 3, 3]}\n"
                          "  element: Si\npotential: {style: sw, file: Si.sw, elements: [Si]}\n"
                          "md: {steps: 40, temperature: 600}\n"
                          "parallel: {decomposition: replicated}\n"
                          "output: {thermo_every: 10, hdf5: false}\n");
    check_two_ranks("meam", "seed: 4\nsystem:\n  lattice: {style: diamond, a: 5.431, cells: [3, 3, 3]}\n"
                            "  element: Si\npotential: {style: meam/spline, file: Si_1.meam.spline, "
                            "elements: [Si]}\nmd: {steps: 40, temperature: 600}\n"
                            "parallel: {decomposition: replicated}\n"
                            "output: {thermo_every: 10, hdf5: false}\n");
}

/* A case error under mpirun: every rank reads the case and fails the same
 * way, the message (file, line, field) is printed once, by rank 0, and
 * mpirun exits non-zero.  Three ranks, so a message from each rank would
 * show. */
Test(parallel, case_error_is_reported_once, .timeout = 300)
{
    thb_mpi_env(3);   /* mpirun as root, 1 thread, no leak checks of Open MPI's */
    const char *path = th_write_temp(7, "bad.yaml",
                                     "system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n"
                                     "  element: Cu\npotential: {style: eam/alloy, file: "
                                     "Cu_mishin1.eam.alloy}\nmd: {steps: 10, temprature: 300}\n");
    char d[512], out[8192];
    snprintf(d, sizeof d, "%s/bad-mpi", th_temp_dir());
    const char *a[] = {"/usr/bin/mpirun", "-np", "3", "--oversubscribe", th_solver(), "run", path,
                       "--out", d, "--quiet", NULL};
    cr_assert_neq(th_run(a, out, sizeof out), 0, "%s", out);
    int lines = 0;
    for (const char *p = out; (p = strstr(p, "error: ")) != NULL; p += 7)
        lines++;
    cr_assert_eq(lines, 1, "want the error once, got %d times:\n%s", lines, out);
    cr_assert(strstr(out, "bad.yaml:5:") && strstr(out, "temprature"), "%s", out);
}

/* Progress under mpirun: every rank runs the loop, rank 0 alone reports it
 * (one "step 50/100" line on 2 ranks, not one per rank). */
Test(parallel, progress_is_reported_once, .timeout = 300)
{
    thb_mpi_env(3);   /* mpirun as root, 1 thread, no leak checks of Open MPI's */
    const char *path = th_write_temp(7, "progress.yaml",
                                     "system:\n  lattice: {style: fcc, a: 3.615, cells: [6, 6, 6]}\n"
                                     "  element: Cu\npotential: {style: eam/alloy, file: "
                                     "Cu_mishin1.eam.alloy}\nmd: {steps: 100}\n"
                                     "output: {thermo_every: 50, hdf5: false}\n");
    char d[512];
    static char out[65536];
    snprintf(d, sizeof d, "%s/progress-mpi", th_temp_dir());
    const char *a[] = {"/usr/bin/mpirun", "-np", "2", "--oversubscribe", th_solver(), "run", path,
                       "--out", d, NULL};
    cr_assert_eq(th_run(a, out, sizeof out), 0, "%s", out);
    int lines = 0;
    for (const char *p = out; (p = strstr(p, "step 50/100")) != NULL; p++)
        lines++;
    cr_assert_eq(lines, 1, "want the progress line once, got %d times:\n%s", lines, out);
}
