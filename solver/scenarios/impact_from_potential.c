/* impact_from_potential: a(T) and the constants at T of a cluster-impact
 * target with the handshake boundary (see impact_from_potential.h). */
#include "scenarios/impact_from_potential.h"

#include <stdlib.h>


int impact_from_potential_given(const json_t *target)
{
    json_t *hs = json_object_get(target, "handshake");
    json_t *th = json_is_object(hs) ? json_object_get(hs, "thermal") : NULL;
    json_t *fp = json_is_object(th) ? json_object_get(th, "from_potential") : NULL;
    return fp != NULL && !json_is_null(fp);
}

int impact_from_potential_read(struct cfg_obj *thermal, double temperature,
                               struct impact_from_potential **out)
{
    struct cfg *cfg = thermal->cfg;
    int present;
    struct cfg_obj o;
    *out = NULL;
    int rc = cfg_section_listed(thermal, "from_potential", &o, &present);
    if (rc || !present)
        return rc;
    struct impact_from_potential *fp = calloc(1, sizeof *fp);
    if (!fp)
        return err_nomem(cfg->err, "from_potential");
    fp->set.md.temperature = temperature;
    if ((rc = cfg_real(&o, "a_min", CFG_REQUIRED, CFG_GT(0), &fp->a_min)) ||
        (rc = cfg_real(&o, "a_max", CFG_REQUIRED, CFG_GT(0), &fp->a_max)) ||
        (rc = cfg_int(&o, "cells", 4, CFG_RANGE(2, 20), &fp->cells)) ||
        (rc = elastic_thermal_read(&o, 0, &fp->set)) || (rc = cfg_close(&o)))
        goto fail;
    if (cfg->shallow == CFG_DESCRIBE)
        goto fail;   /* listed: nothing to compute */
    if (!(fp->a_max > fp->a_min)) {
        rc = cfg_error_at(cfg, "target.handshake.thermal.from_potential.a_max",
                          "a_max = %g must exceed a_min = %g", fp->a_max, fp->a_min);
        goto fail;
    }
    if (!(temperature > 0)) {
        rc = cfg_error_at(cfg, "target.handshake.thermal.from_potential",
                          "computes the lattice constant and the elastic constants at the "
                          "target's temperature: give target.temperature > 0 (at 0 K the "
                          "handshake takes the potential's own)");
        goto fail;
    }
    *out = fp;
    return 0;
fail:
    free(fp);
    return rc;
}

static struct crystal_spec spec_of(const struct impact_from_potential *fp,
                                   enum lattice_style style, const char *element)
{
    return (struct crystal_spec){style, element, 0, fp->cells};
}

int impact_from_potential_a0(const struct impact_from_potential *fp, struct potential *pot,
                             enum lattice_style style, const char *element, double *a0,
                             struct err *e)
{
    struct crystal_spec spec = spec_of(fp, style, element);
    double ecoh;
    return crystal_equilibrium(pot, &spec, fp->a_min, fp->a_max, a0, &ecoh, e);
}

int impact_from_potential_compute(struct impact_from_potential *fp, struct potential *pot,
                                  enum lattice_style style, const char *element, uint64_t seed,
                                  int nthreads, struct run *run, struct err *e)
{
    struct crystal_spec spec = spec_of(fp, style, element);
    struct elastic_thermal_settings s = fp->set;
    s.md.seed = seed;
    s.md.nthreads = nthreads;
    return elastic_thermal_compute_logged("cluster_impact", pot, &spec, fp->a_min, fp->a_max, &s,
                                          run, &fp->out, e);
}
