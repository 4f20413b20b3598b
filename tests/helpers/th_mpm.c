/* th_mpm: MPM test helpers (see th_mpm.h). */
#include "helpers/th_mpm.h"

#include <criterion/criterion.h>

const enum mpm_face_bc th_mpm_faces_free[6] = {MPM_FACE_FREE, MPM_FACE_FREE, MPM_FACE_FREE,
                                               MPM_FACE_FREE, MPM_FACE_FREE, MPM_FACE_FREE};
const enum mpm_face_bc th_mpm_faces_bar[6] = {MPM_FACE_FREE,    MPM_FACE_FREE,
                                              MPM_FACE_SLIDING, MPM_FACE_SLIDING,
                                              MPM_FACE_SLIDING, MPM_FACE_SLIDING};

void th_mpm_uniform(struct mpm *m, const long ncell[3], double h, enum mpm_shape_kind shape,
                    const enum mpm_face_bc faces[6], int nthreads)
{
    struct err e = {0};
    struct mpm_grid g;
    double origin[3] = {0, 0, 0};
    cr_assert_eq(mpm_grid_init_uniform(&g, origin, h, ncell, shape, &e), 0, "%s", e.msg);
    cr_assert_eq(mpm_grid_set_faces(&g, faces, &e), 0, "%s", e.msg);
    cr_assert_eq(mpm_init(m, &g, MPM_MAX_STATE, nthreads, &e), 0, "%s", e.msg);
}

void th_mpm_hier(struct mpm *m, const long ncell[3], double h, const struct mpm_hlevel *levels,
                 int nlevels, enum mpm_hanging hanging, const enum mpm_face_bc faces[6],
                 int nthreads)
{
    struct err e = {0};
    struct mpm_hgrid *hg;
    double origin[3] = {0, 0, 0};
    cr_assert_eq(mpm_hgrid_build(&hg, origin, h, ncell, levels, nlevels, hanging, &e), 0, "%s",
                 e.msg);
    struct mpm_grid g;
    cr_assert_eq(mpm_grid_init_hier(&g, hg, &e), 0, "%s", e.msg);
    cr_assert_eq(mpm_grid_set_faces(&g, faces, &e), 0, "%s", e.msg);
    cr_assert_eq(mpm_init(m, &g, MPM_MAX_STATE, nthreads, &e), 0, "%s", e.msg);
}

int th_mpm_material(struct mpm *m, struct mpm_material *mat)
{
    struct err e = {0};
    cr_assert_not_null(mat);
    int k = mpm_add_material(m, mat, &e);
    cr_assert(k >= 0, "%s", e.msg);
    return k;
}

int th_mpm_box(struct mpm *m, const char *name, int material, const double lo[3],
               const double hi[3], int n, const double v[3], int rigid)
{
    struct err e = {0};
    struct mpm_body b = {.material = material, .rigid = rigid};
    snprintf(b.name, sizeof b.name, "%s", name);
    for (int d = 0; d < 3; d++)
        b.velocity[d] = v ? v[d] : 0.0;
    int k = mpm_add_body(m, &b, &e);
    cr_assert(k >= 0, "%s", e.msg);
    struct region r = {.shape = REGION_BOX};
    for (int d = 0; d < 3; d++) {
        r.lo[d] = lo[d];
        r.hi[d] = hi[d];
    }
    long added, kept;
    cr_assert_eq(mpm_fill_region(m, &r, k, n, NULL, (int64_t)m->pts.n + 1, &added, &kept, &e), 0,
                 "%s", e.msg);
    cr_assert_eq(kept, added);
    cr_assert(added > 0, "body %s has no points", name);
    cr_assert_eq(mpm_prepare(m, &e), 0, "%s", e.msg);
    return k;
}

void th_mpm_run(struct mpm *m, long steps, double cfl)
{
    struct err e = {0};
    for (long s = 0; s < steps; s++) {
        int rc = mpm_step(m, cfl * mpm_stable_dt(m), &e);
        cr_assert_eq(rc, 0, "step %ld: %s", s, e.msg);
    }
}

double th_mpm_mean_stress(const struct mpm *m, int k, double x0, double x1)
{
    double s = 0;
    long n = 0;
    for (long p = 0; p < m->pts.n; p++) {
        double x = m->pts.x0[3 * p];
        if (x >= x0 && x < x1) {
            s += m->pts.stress[6 * p + k];
            n++;
        }
    }
    cr_assert(n > 0, "no points in [%g, %g)", x0, x1);
    return s / n;
}
