/* model_impact_boundary: an impact target's boundary treatment
 * (scenarios/impact_boundary.h) as engine stages (models.h). */
#include "engine/models.h"

static int boundary_pre_force(void *self, struct sim *s, struct err *e)
{
    struct impact_boundary_model *m = self;
    const struct impact_boundary_ops *o = m->bnd->ops;
    return o->pre_step ? o->pre_step(m->bnd, m->md, e) : 0;
}

static int boundary_post_step(void *self, struct sim *s, struct err *e)
{
    struct impact_boundary_model *m = self;
    const struct impact_boundary_ops *o = m->bnd->ops;
    return o->step ? o->step(m->bnd, m->md, e) : 0;
}

/* A stateless treatment is rebuilt from the case: nothing to store. */
static int boundary_checkpoint_none(void *self, struct ckpt *ck, struct err *e)
{
    return 0;
}

const struct sim_model_ops sim_model_impact_boundary = {
    .name = "impact_boundary",
    .pre_force = boundary_pre_force,
    .post_step = boundary_post_step,
    .checkpoint_write = boundary_checkpoint_none,
    .checkpoint_read = boundary_checkpoint_none,
};

/* The same stages for treatments with state of their own: no checkpoints. */
const struct sim_model_ops sim_model_impact_boundary_stateful = {
    .name = "impact_boundary",
    .pre_force = boundary_pre_force,
    .post_step = boundary_post_step,
};
