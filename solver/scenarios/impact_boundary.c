/* impact_boundary: fixed and damped layers (pure MD); the MPM/MD handshake. */
#include "scenarios/impact_boundary.h"

#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "scenarios/handshake_impact.h"

static int fixed_damped_read(struct cfg_obj *t, struct impact_boundary *b)
{
    int rc;
    if ((rc = cfg_real(t, "fixed_thickness", 6.0, CFG_GT(0), &b->fixed_thickness)) ||
        (rc = cfg_real(t, "damped_thickness", 10.0, CFG_GE(0), &b->damped_thickness)) ||
        (rc = cfg_real(t, "damping_time", 0.05, CFG_GT(0), &b->damping_time)))
        return rc;
    return 0;
}

/* Distance of a point from the nearest of the five non-top faces.  A
 * layer is a property of the position at set-up, so on bricks each rank
 * marks its own atoms and an atom keeps its marks when it migrates. */
static double face_distance(const double x[3], const double lo[3], const double hi[3])
{
    double d = x[2] - lo[2];
    for (int k = 0; k < 2; k++) {
        if (x[k] - lo[k] < d) d = x[k] - lo[k];
        if (hi[k] - x[k] < d) d = hi[k] - x[k];
    }
    return d;
}

static int fixed_damped_setup(struct impact_boundary *b, struct md *md, const double lo[3],
                              const double hi[3], struct err *e)
{
    struct particles *p = md->p;
    b->nfixed = b->ndamped = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & IMPACT_GROUP_CLUSTER)
            continue;
        double d = face_distance(p->x + 3 * i, lo, hi);
        if (d < b->fixed_thickness) {
            p->mask[i] |= IMPACT_GROUP_FIXED;
            for (int k = 0; k < 3; k++)
                p->v[3 * i + k] = 0;
            b->nfixed++;
        } else if (d < b->fixed_thickness + b->damped_thickness) {
            p->mask[i] |= IMPACT_GROUP_DAMPED;
            b->ndamped++;
        }
    }
    if (md->halo) {   /* bricks: every rank marked its own atoms */
        double n[2] = {(double)b->nfixed, (double)b->ndamped};
        halo_sum(md->halo, n, 2);
        b->nfixed = (long)n[0];
        b->ndamped = (long)n[1];
    }
    md->frozen_mask = IMPACT_GROUP_FIXED;
    if (b->damped_thickness > 0) {
        /* Langevin bath at the target temperature: friction m / damping_time */
        md->thermo.style = THERMOSTAT_LANGEVIN;
        md->thermo.temperature = b->temperature;
        md->thermo.tau = b->damping_time;
        md->thermo.group_mask = IMPACT_GROUP_DAMPED;
    }
    (void)e;
    return 0;
}

static uint32_t fixed_damped_exclude(const struct impact_boundary *b)
{
    (void)b;
    return IMPACT_GROUP_FIXED | IMPACT_GROUP_DAMPED;
}

const struct impact_boundary_ops impact_boundaries[] = {
    {"fixed_damped", fixed_damped_read, fixed_damped_setup, NULL, fixed_damped_exclude, NULL,
     NULL, NULL, NULL, 1, NULL, NULL, NULL, NULL, NULL, NULL},
    {"handshake", handshake_impact_read, handshake_impact_setup, NULL, handshake_impact_exclude,
     handshake_impact_destroy, handshake_impact_prepare, handshake_impact_pre_step,
     handshake_impact_report, 0, handshake_impact_checkpoint_write,
     handshake_impact_checkpoint_read, handshake_impact_checkpoint_sync,
     handshake_impact_add_particles, handshake_impact_checkpoint_collect,
     handshake_impact_checkpoint_write_part},
    {NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, 0, NULL, NULL, NULL, NULL, NULL, NULL},
};

int impact_boundary_read(struct cfg_obj *target, struct impact_boundary *b)
{
    const char *names[8];
    int n = 0;
    for (; impact_boundaries[n].name && n < 7; n++)
        names[n] = impact_boundaries[n].name;
    names[n] = NULL;
    int k, rc = cfg_enum(target, "boundary", "fixed_damped", names, &k);
    if (rc)
        return rc;
    memset(b, 0, sizeof *b);
    b->ops = &impact_boundaries[k];
    return b->ops->read(target, b);
}

void impact_boundary_free(struct impact_boundary *b)
{
    if (b->ops && b->ops->destroy)
        b->ops->destroy(b);
    b->data = NULL;
    free(b->from_potential);
    b->from_potential = NULL;
}
