/*
 * What ParaView reads from fields.xdmf: the component it labels XY of a
 * stress field holds sigma_xy, and each particle snapshot carries its
 * simulation cell (HDF5 datasets with units, a box outline in the XDMF).
 *
 * The crystal: fcc Cu (Mishin EAM, a = 3.615 Å) with x along [210],
 * y along [-120], z along [001], stretched homogeneously along x by
 * strain eps.  In this frame the cubic crystal couples a normal strain to
 * a shear stress: sigma_xy = C'_xyxx eps, with C' the cubic constants
 * rotated by atan(1/2) about z (+25.2 GPa; it is 0 along the cube axes,
 * and sigma_xz, sigma_yz stay 0 by symmetry).  The expected value is computed here from the potential's 0 K
 * constants published with it (Mishin et al., PRB 63, 224106 (2001),
 * Table III: C11 169.9, C12 122.6, C44 76.2 GPa); a central difference
 * over eps = +-0.002 removes the second-order term, so the tolerance
 * (1 %; measured 0.03 %) covers the rounding of those constants.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/elements.h"
#include "core/lattice.h"
#include "helpers/th.h"
#include "output/lammps_data_write.h"

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    cr_assert_not_null(s);
    cr_assert_eq(fread(s, 1, (size_t)n, f), (size_t)n);
    s[n] = '\0';
    fclose(f);
    return s;
}

/* The [210] [-120] [001] crystal of 2 x 2 x 4 cells stretched by 1 + eps
 * along x, written as a LAMMPS data file; the run of 0 steps writes its
 * snapshot. */
static void run_stretched(double eps, const char *tag, char *outdir, size_t len, double hi[3],
                          long *natoms)
{
    struct lattice l = {LATTICE_FCC, 3.615, {0, 0, 0}, {{2, 1, 0}, {-1, 2, 0}, {0, 0, 1}}};
    struct particles *p = particles_create(512);
    int t = particles_type_index(p, "Cu", element_mass("Cu"));
    int64_t id = 1;
    long cells[3] = {2, 2, 4};
    struct err e = {0};
    cr_assert(lattice_fill(&l, cells, NULL, p, t, &id, &e) > 0, "%s", e.msg);
    double cell[3];
    lattice_cell(&l, cell);
    struct box b = {0};
    for (int d = 0; d < 3; d++) {
        b.lo[d] = 0;
        b.hi[d] = cells[d] * cell[d] * (d == 0 ? 1.0 + eps : 1.0);
        b.bc[d] = BOUNDARY_PERIODIC;
        hi[d] = b.hi[d];
    }
    for (int i = 0; i < p->n_owned; i++)
        p->x[3 * i] *= 1.0 + eps;
    *natoms = p->n_owned;
    char data[1024], name[64], yaml[2048];
    snprintf(data, sizeof data, "%s/%s.data", th_temp_dir(), tag);
    cr_assert_eq(lammps_data_write(data, p, &b, "stretched [210] Cu", &e), 0, "%s", e.msg);
    particles_destroy(&p);
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\nmd: {steps: 0}\n",
             data);
    snprintf(name, sizeof name, "%s.yaml", tag);
    const char *path = th_write_temp(6, name, yaml);
    snprintf(outdir, len, "%s/%s-out", th_temp_dir(), tag);
    const char *argv[] = {th_solver(), "run", path, "--out", outdir, "--quiet", NULL};
    char out[4096];
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 0, "exit %d: %s", rc, out);
}

/* Mean over the particles of the attribute the XDMF names `label` in the
 * grid of step 0: the XDMF is read as ParaView reads it (the HyperSlab's
 * start, stride and count select one column of the HDF5 dataset it
 * names). */
static double xdmf_component_mean(const char *dir, const char *label, long natoms,
                                  double *spread)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/fields.xdmf", dir);
    char *x = slurp(path);
    char key[128];
    snprintf(key, sizeof key, "<Attribute Name=\"%s\"", label);
    const char *a = strstr(x, key);
    cr_assert_not_null(a, "no attribute '%s' in %s", label, path);
    const char *end = strstr(a, "</Attribute>");
    cr_assert_not_null(end);
    const char *hs = strstr(a, "ItemType=\"HyperSlab\"");
    cr_assert(hs && hs < end, "'%s' is not a HyperSlab", label);
    const char *sel = strstr(hs, "Dimensions=\"3 2\" Format=\"XML\">");
    cr_assert(sel && sel < end);
    long st[2], sd[2], cnt[2];
    cr_assert_eq(sscanf(strchr(sel, '>') + 1, "%ld %ld %ld %ld %ld %ld", &st[0], &st[1], &sd[0],
                        &sd[1], &cnt[0], &cnt[1]), 6);
    cr_assert(st[0] == 0 && sd[0] == 1 && cnt[0] == natoms && cnt[1] == 1,
              "hyperslab %ld %ld / %ld %ld / %ld %ld", st[0], st[1], sd[0], sd[1], cnt[0], cnt[1]);
    const char *src = strstr(sel, "Format=\"HDF\">");
    cr_assert(src && src < end);
    src = strchr(src, '>') + 1;
    const char *colon = strchr(src, ':');
    char file[256], dset[256];
    snprintf(file, sizeof file, "%.*s", (int)(colon - src), src);
    snprintf(dset, sizeof dset, "%.*s", (int)(strchr(colon, '<') - colon - 1), colon + 1);
    free(x);
    snprintf(path, sizeof path, "%s/%s", dir, file);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0, "%s", path);
    hid_t ds = H5Dopen2(f, dset, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s:%s", path, dset);
    double *v = malloc((size_t)natoms * 6 * sizeof *v);
    cr_assert_not_null(v);
    cr_assert(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    H5Fclose(f);
    double sum = 0, mn = INFINITY, mx = -INFINITY;
    for (long i = 0; i < natoms; i++) {
        double s = v[6 * i + st[1]];
        sum += s;
        mn = fmin(mn, s);
        mx = fmax(mx, s);
    }
    free(v);
    *spread = mx - mn;
    return sum / natoms;
}

/* C'_ijkl = R_ip R_jq R_kr R_ls C_pqrs of the cubic constants, R's rows
 * the unit vectors of x, y, z in crystal axes. */
static double rotated_c(const double R[3][3], int i, int j, int k, int l)
{
    const double c11 = 169.9, c12 = 122.6, c44 = 76.2;   /* GPa, Mishin 2001 */
    double sum = 0;
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++) {
                    double c = 0;
                    if (p == q && r == s)
                        c = p == r ? c11 : c12;
                    else if ((p == r && q == s) || (p == s && q == r))
                        c = c44;
                    if (c != 0)
                        sum += R[i][p] * R[j][q] * R[k][r] * R[l][s] * c;
                }
    return sum;
}

Test(output_xdmf, xy_component_holds_sigma_xy_of_a_stretched_rotated_crystal)
{
    const double eps = 0.002;
    char dp[1024], dm[1024];
    double hp[3], hm[3];
    long np, nm;
    run_stretched(+eps, "plus", dp, sizeof dp, hp, &np);
    run_stretched(-eps, "minus", dm, sizeof dm, hm, &nm);
    cr_assert_eq(np, 320);
    cr_assert_eq(nm, np);
    const double r5 = sqrt(5.0);
    const double R[3][3] = {{2 / r5, 1 / r5, 0}, {-1 / r5, 2 / r5, 0}, {0, 0, 1}};
    static const struct {
        const char *label;
        int i, j;
    } comp[] = {{"stress_xx [GPa]", 0, 0}, {"stress_yy [GPa]", 1, 1}, {"stress_zz [GPa]", 2, 2},
                {"stress_xy [GPa]", 0, 1}, {"stress_xz [GPa]", 0, 2}, {"stress_yz [GPa]", 1, 2}};
    for (size_t c = 0; c < sizeof comp / sizeof comp[0]; c++) {
        double sp, sm;
        double plus = xdmf_component_mean(dp, comp[c].label, np, &sp);
        double minus = xdmf_component_mean(dm, comp[c].label, nm, &sm);
        /* every atom of a homogeneously strained Bravais lattice has the
         * same environment */
        cr_assert_lt(fmax(sp, sm), 1e-9, "%s spread %g GPa", comp[c].label, fmax(sp, sm));
        double slope = (plus - minus) / (2 * eps);
        double want = rotated_c(R, comp[c].i, comp[c].j, 0, 0);
        cr_log_info("%s: d sigma / d eps_xx = %.3f GPa, from the elastic constants %.3f GPa",
                    comp[c].label, slope, want);
        if (fabs(want) < 1e-9)
            cr_assert_lt(fabs(plus) + fabs(minus), 1e-6, "%s: %g, %g GPa (0 by symmetry)",
                         comp[c].label, plus, minus);
        else
            cr_assert_lt(fabs(slope - want), 0.01 * fabs(want), "%s: %.4f GPa vs %.4f GPa",
                         comp[c].label, slope, want);
    }
    /* the shear coupling is what tells XY from the other components */
    double want_xy = rotated_c(R, 0, 1, 0, 0);
    cr_assert(want_xy > 20 && want_xy < 30, "C'_xyxx %g GPa", want_xy);
}

static void read_vec3(hid_t f, const char *name, double out[3], char *unit, size_t ulen)
{
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s missing", name);
    cr_assert(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0);
    hid_t a = H5Aopen(ds, "unit", H5P_DEFAULT);
    cr_assert(a >= 0, "%s has no unit", name);
    hid_t t = H5Aget_type(a);
    size_t n = H5Tget_size(t);
    cr_assert_lt(n, ulen);
    memset(unit, 0, ulen);
    H5Aread(a, t, unit);
    H5Tclose(t);
    H5Aclose(a);
    H5Dclose(ds);
}

Test(output_xdmf, snapshot_carries_its_cell)
{
    char dir[1024];
    double hi[3];
    long n;
    run_stretched(0.001, "cell", dir, sizeof dir, hi, &n);
    char path[1200], unit[32];
    snprintf(path, sizeof path, "%s/fields.h5", dir);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    double lo[3], h[3], tilt[3], pbc[3];
    read_vec3(f, "/particles/00000000/cell/lo", lo, unit, sizeof unit);
    cr_assert_str_eq(unit, "Å");
    read_vec3(f, "/particles/00000000/cell/hi", h, unit, sizeof unit);
    cr_assert_str_eq(unit, "Å");
    read_vec3(f, "/particles/00000000/cell/tilt", tilt, unit, sizeof unit);
    read_vec3(f, "/particles/00000000/cell/pbc", pbc, unit, sizeof unit);
    cr_assert_str_eq(unit, "1");
    for (int d = 0; d < 3; d++) {
        cr_assert_eq(lo[d], 0.0);
        cr_assert_lt(fabs(h[d] - hi[d]), 1e-12 * hi[d], "hi[%d] %.17g vs %.17g", d, h[d], hi[d]);
        cr_assert_eq(tilt[d], 0.0);
        cr_assert_eq(pbc[d], 1.0);
    }
    H5Fclose(f);
    /* the XDMF's cell collection: the outline's far corner is hi */
    snprintf(path, sizeof path, "%s/fields.xdmf", dir);
    char *x = slurp(path);
    const char *g = strstr(x, "<Grid Name=\"cell_0\"");
    cr_assert_not_null(g, "no cell grid in the XDMF");
    cr_assert(strstr(g, "TopologyType=\"Polyline\" NumberOfElements=\"12\""));
    const char *geo = strstr(g, "Dimensions=\"8 3\"");
    cr_assert_not_null(geo);
    geo = strchr(geo, '>') + 1;
    double c[24];
    char *next = (char *)geo;
    for (int k = 0; k < 24; k++)
        c[k] = strtod(next, &next);
    for (int d = 0; d < 3; d++) {
        cr_assert_eq(c[d], 0.0);
        cr_assert_lt(fabs(c[21 + d] - hi[d]), 1e-12 * hi[d]);
    }
    free(x);
}
