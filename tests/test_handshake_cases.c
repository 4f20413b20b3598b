/*
 * MPM/MD handshake case files (Guo & Yang 2005, section 2.2): bad region
 * layouts -- a region narrower than the potential cutoff, the MD region and
 * its handshake touching the coarse grid, no room for regions II and III,
 * a cell that does not fit the lattice -- are refused by `check` with the
 * file, line, key and reason; a small wave-packet run writes the region of
 * every atom and material point to the HDF5 snapshots (what ParaView
 * colours by), the stress profile from both sides, and the transmitted
 * energy as a metric.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "input/case.h"

#define HEAD                                                                                      \
    "type: handshake_wave\n"                                                                      \
    "crystal: {element: Cu, a_min: 3.5, a_max: 3.7}\n"                                            \
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"

static int check_text(const char *yaml, char *msg, size_t len)
{
    const char *path = th_write_temp(1, "hs.yaml", yaml);
    struct case_doc cd;
    struct case_resolved cr;
    struct err e = {0};
    int rc = case_load_file(&cd, path, &e);
    if (!rc)
        rc = case_resolve(&cd, 0, 1, NULL, &cr, &e);
    if (!rc)
        case_resolved_free(&cr);
    snprintf(msg, len, "%s", e.msg);
    case_doc_free(&cd);
    return rc;
}

Test(handshake_cases, good_case_checks, .timeout = 60)
{
    char msg[2048];
    int rc = check_text(HEAD "bar: {mpm: [16, 16], md: 12, width: 4}\nmd: {steps: 10}\n", msg,
                        sizeof msg);
    cr_assert_eq(rc, 0, "%s", msg);
}

Test(handshake_cases, region_narrower_than_cutoff_refused, .timeout = 60)
{
    char msg[2048];
    int rc = check_text(HEAD "handshake:\n  regions: [2, 1.5, 2]\n"
                             "bar: {mpm: [16, 16], md: 12, width: 4}\n",
                        msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "hs.yaml:5:") && strstr(msg, "handshake.regions") &&
                  strstr(msg, "region II is") && strstr(msg, "narrower than the potential cutoff"),
              "%s", msg);
}

Test(handshake_cases, md_touching_coarse_grid_refused, .timeout = 60)
{
    char msg[2048];
    int rc = check_text(HEAD "handshake:\n  levels: 2\n  fine: 3\n"
                             "bar: {mpm: [16, 16], md: 12, width: 4}\n",
                        msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "hs.yaml:6:") && strstr(msg, "handshake.fine") &&
                  strstr(msg, "must not touch the coarse grid"),
              "%s", msg);
}

Test(handshake_cases, no_room_for_regions_II_and_III_refused, .timeout = 60)
{
    char msg[2048];
    int rc = check_text(HEAD "bar:\n  mpm: [3, 16]\n  md: 12\n  width: 4\n", msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "hs.yaml:5:") && strstr(msg, "bar.mpm") &&
                  strstr(msg, "less than regions II and III"),
              "%s", msg);
}

Test(handshake_cases, cell_off_lattice_refused, .timeout = 60)
{
    char msg[2048];
    int rc = check_text(HEAD "handshake:\n  cell: 0.75\nbar: {mpm: [16, 16], md: 12, width: 4}\n",
                        msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "hs.yaml:5:") && strstr(msg, "handshake.cell") &&
                  strstr(msg, "1 or 0.5 lattice constants"),
              "%s", msg);
}

Test(handshake_cases, packet_too_close_to_handshake_refused, .timeout = 60)
{
    char msg[2048];
    int rc = check_text("type: handshake_packet\n"
                        "crystal: {element: Cu, a_min: 3.5, a_max: 3.7}\n"
                        "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                        "packet:\n  sigma: 1.5\n  center: 6\n"
                        "measure_time: 1\n",
                        msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "hs.yaml:6:") && strstr(msg, "packet.center") &&
                  strstr(msg, "inside the handshake"),
              "%s", msg);
}

/* Read an integer dataset into a new array; *n gets its length. */
static long *read_ints(hid_t f, const char *name, long *n)
{
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s missing", name);
    hid_t sp = H5Dget_space(ds);
    hsize_t dims[2];
    H5Sget_simple_extent_dims(sp, dims, NULL);
    *n = (long)dims[0];
    long *v = malloc((size_t)*n * sizeof *v);
    H5Dread(ds, H5T_NATIVE_LONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
    H5Sclose(sp);
    H5Dclose(ds);
    return v;
}

Test(handshake_cases, packet_run_writes_regions_profile_and_transmission, .timeout = 600)
{
    const char *path = th_write_temp(2, "packet.yaml",
                                     "type: handshake_packet\n"
                                     "crystal: {element: Cu, a_min: 3.5, a_max: 3.7}\n"
                                     "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                                     "bar: {mpm: [16, 0], md: 46, width: 3}\n"
                                     "packet: {sigma: 1, center: 14, fixed: 2}\n"
                                     "profile: {every: 100}\n"
                                     "output: {thermo_every: 50, snapshot_every: 1000}\n");
    char dir[1200];
    snprintf(dir, sizeof dir, "%s/packet-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    char out[8192];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    char p[1400];
    snprintf(p, sizeof p, "%s/result.json", dir);
    json_t *r = json_load_file(p, 0, NULL);
    cr_assert_not_null(r);
    json_t *m = json_object_get(r, "metrics");
    double tf = json_real_value(json_object_get(json_object_get(m, "transmitted_fraction"), "value"));
    double ref = json_real_value(
        json_object_get(json_object_get(m, "reference_fraction_of_packet"), "value"));
    cr_log_info("small packet run: transmitted %.3f, reference half %.3f", tf, ref);
    cr_expect(tf > 0.5 && tf < 1.05, "transmitted fraction %g", tf);
    cr_expect_lt(fabs(ref - 0.5), 0.02, "reference packet holds %g of the energy", ref);
    json_decref(r);
    /* regions in the first snapshot: atoms 0, 1, 5 and copies 2, 3; points 2, 3, 4 */
    snprintf(p, sizeof p, "%s/fields.h5", dir);
    hid_t f = H5Fopen(p, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    long n, cnt[6] = {0};
    long *reg = read_ints(f, "/particles/00000000/region", &n);
    for (long i = 0; i < n; i++) {
        cr_assert(reg[i] >= 0 && reg[i] <= 5, "region %ld", reg[i]);
        cnt[reg[i]]++;
    }
    free(reg);
    cr_expect(cnt[0] > 0 && cnt[1] > 0 && cnt[2] > 0 && cnt[3] > 0 && cnt[5] > 0 && cnt[4] == 0,
              "atom regions %ld %ld %ld %ld %ld %ld", cnt[0], cnt[1], cnt[2], cnt[3], cnt[4],
              cnt[5]);
    memset(cnt, 0, sizeof cnt);
    reg = read_ints(f, "/points/00000000/region", &n);
    for (long i = 0; i < n; i++) {
        cr_assert(reg[i] >= 2 && reg[i] <= 4, "point region %ld", reg[i]);
        cnt[reg[i]]++;
    }
    free(reg);
    cr_expect(cnt[2] > 0 && cnt[3] > 0 && cnt[4] > 0, "point regions %ld %ld %ld", cnt[2], cnt[3],
              cnt[4]);
    H5Fclose(f);
    /* the XDMF shows the region as a scalar of both collections */
    snprintf(p, sizeof p, "%s/fields.xdmf", dir);
    FILE *x = fopen(p, "r");
    cr_assert_not_null(x);
    static char buf[1 << 20];
    size_t nb = fread(buf, 1, sizeof buf - 1, x);
    buf[nb] = 0;
    fclose(x);
    cr_expect(strstr(buf, "particles/00000000/region") && strstr(buf, "points/00000000/region"));
    /* the profile has MD and MPM slabs */
    snprintf(p, sizeof p, "%s/profile.csv", dir);
    x = fopen(p, "r");
    cr_assert_not_null(x);
    nb = fread(buf, 1, sizeof buf - 1, x);
    buf[nb] = 0;
    fclose(x);
    cr_expect(strstr(buf, "step,time_ps,x_A,source") && strstr(buf, ",0,") && strstr(buf, ",1,"));
}
