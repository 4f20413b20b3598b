/* th_dpd: DPD test helpers (see th_dpd.h). */
#include "helpers/th_dpd.h"

#include <criterion/criterion.h>
#include <string.h>

#include "helpers/th.h"

void th_cg_params(struct cg_params *prm)
{
    memset(prm, 0, sizeof *prm);
    snprintf(prm->element, sizeof prm->element, "Cu");
    prm->sc = (struct sc_params){0.1, 39.0, 7.23, 9, 6, 10.845, 0, 0, 0, 0, 0, 0};
    sc_params_finish(&prm->sc);
    prm->mass = 8 * 63.546;
    prm->atoms_per_particle = 8;
    prm->lattice_constant = 7.23;
}

struct dpd_settings th_dpd_settings(enum dpd_variant v, double gamma, double T)
{
    struct dpd_settings s = {.variant = v, .gamma = gamma, .temperature = T, .cutoff = 10.845,
                             .heat_capacity = 21.0};
    return s;
}

void th_dpd(struct dpd *d, long n, double a, int periodic, double displace,
            const struct dpd_settings *set, double dt, int nthreads, uint64_t seed)
{
    struct box box = {0};
    struct particles *p = th_crystal(LATTICE_FCC, a, n, "Cu", displace, 7, &box);
    if (!periodic)
        for (int k = 0; k < 3; k++)
            box.bc[k] = BOUNDARY_FREE;
    struct cg_params prm;
    th_cg_params(&prm);
    struct err e = {0};
    int rc = dpd_init(d, p, &box, &prm, set, dt, 1.0, nthreads, seed, &e);
    cr_assert_eq(rc, 0, "dpd_init: %s", e.msg);
}
