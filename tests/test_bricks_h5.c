/*
 * Collective parallel HDF5 (docs/parallel.md, "Output"): under `mpirun
 * -np N` a brick run writes its one fields.h5 and its checkpoints with
 * every rank writing its own atoms' rows (MPI-IO, collective transfers).
 * The files must be the serial run's files: the same datasets with the
 * same types, shapes, chunks and filters, every atom once (rows in rank
 * order, so matched by id), the values those of the serial trajectory to
 * 1e-10 relative (the force sums run in another order on bricks), and
 * the same XDMF description (ParaView opens it the same way).  5324 LJ
 * atoms, so the per-particle datasets are chunked and compressed (more
 * than 4096 rows), on 2 and 3 ranks (3 bricks: uneven counts and
 * offsets).
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10
#define NATOMS 5324L   /* fcc 11 x 11 x 11 cells */

static const char *case_text =
    "seed: 5\nsystem:\n  lattice: {style: fcc, a: 5.26, cells: [11, 11, 11]}\n  element: Ar\n"
    "potential: {style: lj, elements: [Ar], epsilon: [0.0104], sigma: [3.4], cutoff: 8.5}\n"
    "md: {steps: 20, temperature: 60, timestep: 0.002}\n"
    "output: {thermo_every: 5, snapshot_every: 10, checkpoint_every: 10}\n";

/* Type, shape, chunks and filters of a dataset of two files agree. */
static void same_layout(hid_t fa, hid_t fb, const char *name, const char *tag)
{
    hid_t a = H5Dopen2(fa, name, H5P_DEFAULT), b = H5Dopen2(fb, name, H5P_DEFAULT);
    cr_assert(a >= 0 && b >= 0, "%s: %s missing", tag, name);
    hid_t ta = H5Dget_type(a), tb = H5Dget_type(b);
    cr_assert_gt(H5Tequal(ta, tb), 0, "%s: %s: another type", tag, name);
    hid_t sa = H5Dget_space(a), sb = H5Dget_space(b);
    hsize_t da[4] = {0}, db[4] = {0};
    int ra = H5Sget_simple_extent_dims(sa, da, NULL), rb = H5Sget_simple_extent_dims(sb, db, NULL);
    cr_assert_eq(ra, rb, "%s: %s: rank %d vs %d", tag, name, ra, rb);
    for (int k = 0; k < ra; k++)
        cr_assert_eq(da[k], db[k], "%s: %s: dimension %d: %llu vs %llu", tag, name, k,
                     (unsigned long long)da[k], (unsigned long long)db[k]);
    hid_t pa = H5Dget_create_plist(a), pb = H5Dget_create_plist(b);
    cr_assert_eq(H5Pget_layout(pa), H5Pget_layout(pb), "%s: %s: layout", tag, name);
    if (H5Pget_layout(pa) == H5D_CHUNKED) {
        hsize_t ca[4] = {0}, cb[4] = {0};
        cr_assert_eq(H5Pget_chunk(pa, 4, ca), H5Pget_chunk(pb, 4, cb));
        for (int k = 0; k < ra; k++)
            cr_assert_eq(ca[k], cb[k], "%s: %s: chunk dimension %d", tag, name, k);
        int na = H5Pget_nfilters(pa), nb = H5Pget_nfilters(pb);
        cr_assert_eq(na, nb, "%s: %s: %d vs %d filters", tag, name, na, nb);
        cr_assert_gt(na, 0, "%s: %s: a chunked dataset without filters", tag, name);
        for (int k = 0; k < na; k++) {
            unsigned flags;
            size_t nel = 0;
            H5Z_filter_t fa_id = H5Pget_filter2(pa, (unsigned)k, &flags, &nel, NULL, 0, NULL, NULL);
            nel = 0;
            H5Z_filter_t fb_id = H5Pget_filter2(pb, (unsigned)k, &flags, &nel, NULL, 0, NULL, NULL);
            cr_assert_eq(fa_id, fb_id, "%s: %s: filter %d", tag, name, k);
        }
    }
    H5Pclose(pa);
    H5Pclose(pb);
    H5Sclose(sa);
    H5Sclose(sb);
    H5Tclose(ta);
    H5Tclose(tb);
    H5Dclose(a);
    H5Dclose(b);
}

/* The n ids of a dataset (new buffer). */
static int64_t *read_ids(hid_t f, const char *name, long *n)
{
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    cr_assert_geq(ds, 0, "%s", name);
    hid_t sp = H5Dget_space(ds);
    *n = (long)H5Sget_simple_extent_npoints(sp);
    int64_t *id = malloc((size_t)(*n > 0 ? *n : 1) * sizeof *id);
    cr_assert_not_null(id);
    cr_assert_geq(H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, id), 0);
    H5Sclose(sp);
    H5Dclose(ds);
    return id;
}

/* Every id of `a` exactly once in `b`: ids are 1..NATOMS. */
static void same_ids(hid_t fa, hid_t fb, const char *name, const char *tag)
{
    long na, nb;
    int64_t *a = read_ids(fa, name, &na), *b = read_ids(fb, name, &nb);
    cr_assert_eq(na, NATOMS, "%s: %s: %ld ids", tag, name, na);
    cr_assert_eq(nb, NATOMS, "%s: %s: %ld ids", tag, name, nb);
    char *seen = calloc((size_t)NATOMS + 1, 1);
    cr_assert_not_null(seen);
    for (long i = 0; i < nb; i++) {
        cr_assert(b[i] >= 1 && b[i] <= NATOMS, "%s: %s: id %lld", tag, name, (long long)b[i]);
        cr_assert_eq(seen[b[i]], 0, "%s: %s: id %lld twice", tag, name, (long long)b[i]);
        seen[b[i]] = 1;
    }
    for (long i = 0; i < na; i++)
        cr_assert_eq(seen[a[i]], 1, "%s: %s: id %lld missing", tag, name, (long long)a[i]);
    free(seen);
    free(a);
    free(b);
}

static hid_t open_file(const char *dir, const char *name)
{
    char path[800];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert_geq(f, 0, "%s", path);
    return f;
}

/* fields.xdmf after its first comment line (the build that wrote it). */
static void read_xdmf_body(const char *dir, char *buf, size_t len)
{
    thb_read_text(dir, "fields.xdmf", buf, len);
    char *c = strstr(buf, "-->");
    cr_assert_not_null(c, "%s/fields.xdmf: no provenance comment", dir);
    memmove(buf, c, strlen(c) + 1);
}

static const char *const snapshot_sets[] = {"position", "velocity", "force", "id",
                                            "type",     "pe",       "stress", NULL};

Test(bricks_h5, collective_files_have_the_serial_layout, .timeout = 900)
{
    const char *path = th_write_temp(0, "ph5.yaml", case_text);
    char serial[600];
    snprintf(serial, sizeof serial, "%s/ph5-serial", th_temp_dir());
    thb_must_run(path, 0, serial, NULL);
    static char xs[1 << 20], xp[1 << 20];
    read_xdmf_body(serial, xs, sizeof xs);
    const int nps[] = {2, 3};
    for (int k = 0; k < 2; k++) {
        char dir[600], tag[64];
        snprintf(dir, sizeof dir, "%s/ph5-%d", th_temp_dir(), nps[k]);
        snprintf(tag, sizeof tag, "%d ranks", nps[k]);
        thb_must_run(path, nps[k], dir, NULL);
        thb_check_parallel_record(dir, nps[k], NATOMS);
        hid_t fs = open_file(serial, "fields.h5"), fp = open_file(dir, "fields.h5");
        for (long step = 0; step <= 20; step += 10) {
            char group[64], name[128];
            snprintf(group, sizeof group, "/particles/%08ld", step);
            for (int s = 0; snapshot_sets[s]; s++) {
                snprintf(name, sizeof name, "%s/%s", group, snapshot_sets[s]);
                same_layout(fs, fp, name, tag);
            }
            snprintf(name, sizeof name, "%s/id", group);
            same_ids(fs, fp, name, tag);
        }
        /* the values of the last snapshot (at step 0 the forces of the
         * perfect lattice are round-off, 1e-16 eV/Å) */
        static const char *const vals[] = {"position", "velocity", "force", "pe", "stress", NULL};
        static const int ncomp[] = {3, 3, 3, 1, 6};
        thb_compare_snapshot(serial, dir, "/particles/00000020", vals, ncomp, REL, tag);
        H5Fclose(fs);
        H5Fclose(fp);
        /* the checkpoint: the same particle datasets, every atom once */
        hid_t cs = open_file(serial, "checkpoint-0000000010.h5"),
              cp = open_file(dir, "checkpoint-0000000010.h5");
        static const char *const ck_sets[] = {"x", "v", "f", "type", "id", "mask", "image",
                                              "pe", "virial", NULL};
        for (int s = 0; ck_sets[s]; s++) {
            char name[128];
            snprintf(name, sizeof name, "/model/md/atoms/%s", ck_sets[s]);
            same_layout(cs, cp, name, tag);
        }
        same_ids(cs, cp, "/model/md/atoms/id", tag);
        H5Fclose(cs);
        H5Fclose(cp);
        /* ParaView reads the same description: the XDMF is the serial one */
        read_xdmf_body(dir, xp, sizeof xp);
        cr_assert_str_eq(xs, xp, "%s: fields.xdmf differs from the serial run's", tag);
    }
}
