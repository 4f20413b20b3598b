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

/* A stateless treatment is rebuilt from the case: nothing to store; one
 * with state of its own stores it under model/impact_boundary/state. */
static int boundary_checkpoint_write(void *self, struct ckpt *ck, struct err *e)
{
    struct impact_boundary_model *m = self;
    const struct impact_boundary_ops *o = m->bnd->ops;
    return o->checkpoint_write ? o->checkpoint_write(m->bnd, ck, "model/impact_boundary/state")
                               : 0;
}

static int boundary_checkpoint_read(void *self, struct ckpt *ck, struct err *e)
{
    struct impact_boundary_model *m = self;
    const struct impact_boundary_ops *o = m->bnd->ops;
    return o->checkpoint_read ? o->checkpoint_read(m->bnd, ck, "model/impact_boundary/state") : 0;
}

static int boundary_checkpoint_collect(void *self, struct err *e)
{
    struct impact_boundary_model *m = self;
    const struct impact_boundary_ops *o = m->bnd->ops;
    return o->checkpoint_collect ? o->checkpoint_collect(m->bnd, e) : 0;
}

static int boundary_checkpoint_write_part(void *self, struct ckpt *ck, struct err *e)
{
    struct impact_boundary_model *m = self;
    const struct impact_boundary_ops *o = m->bnd->ops;
    (void)e;
    return o->checkpoint_write_part
               ? o->checkpoint_write_part(m->bnd, ck, "model/impact_boundary/state")
               : 0;
}

static void boundary_checkpoint_sync(void *self)
{
    struct impact_boundary_model *m = self;
    if (m->bnd->ops->checkpoint_sync)
        m->bnd->ops->checkpoint_sync(m->bnd);
}

const struct sim_model_ops sim_model_impact_boundary = {
    .name = "impact_boundary",
    .pre_force = boundary_pre_force,
    .post_step = boundary_post_step,
    .checkpoint_write = boundary_checkpoint_write,
    .checkpoint_read = boundary_checkpoint_read,
    .checkpoint_sync = boundary_checkpoint_sync,
    .checkpoint_collect = boundary_checkpoint_collect,
    .checkpoint_write_part = boundary_checkpoint_write_part,
};

/* The same stages for a treatment with state that checkpoints cannot hold. */
const struct sim_model_ops sim_model_impact_boundary_stateful = {
    .name = "impact_boundary",
    .pre_force = boundary_pre_force,
    .post_step = boundary_post_step,
};
