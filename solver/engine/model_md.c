/* model_md: molecular dynamics as engine stages (models.h). */
#include "engine/models.h"

static int md_model_init(void *self, struct sim *s, struct err *e)
{
    struct md_model *m = self;
    m->md->peratom = s->peratom || m->peratom_always;
    return md_compute_forces(m->md, e);
}

static int md_model_pre_force(void *self, struct sim *s, struct err *e)
{
    struct md_model *m = self;
    /* the step being taken is s->step + 1 */
    m->md->peratom = s->peratom || m->peratom_always ||
                     (m->peratom_every > 0 && (s->step + 1) % m->peratom_every == 0);
    md_step_drift(m->md);
    return 0;
}

static int md_model_force(void *self, struct sim *s, struct err *e)
{
    struct md_model *m = self;
    return md_step_forces(m->md, e);
}

static int md_model_integrate(void *self, struct sim *s, struct err *e)
{
    struct md_model *m = self;
    md_step_kick(m->md);
    return 0;
}

static void md_model_observe(void *self, const struct sim *s, struct sim_energy *en)
{
    struct md_model *m = self;
    const struct md *md = m->md;
    en->total = md->last.energy + md_kinetic_energy(md);
    /* energy is conserved without a thermostat and without held groups */
    en->conserved = md->thermo.style == THERMOSTAT_NONE;
    en->scale = md->p->n_owned > 0 ? md->p->n_owned : 1;
    en->limit = m->max_energy_change;
    en->limit_key = "md.max_energy_change";
    en->unit = "eV/atom";
}

static int md_model_checkpoint_write(void *self, struct ckpt *ck, struct err *e)
{
    struct md_model *m = self;
    const struct md *md = m->md;
    int rc = ckpt_put_long(ck, "step", md->step);
    if (!rc) rc = ckpt_put_double(ck, "time", md->time);
    if (!rc) rc = ckpt_put_long(ck, "nrebuilds", md->nrebuilds);
    if (!rc) rc = ckpt_put_double(ck, "energy", md->last.energy);
    if (!rc) rc = ckpt_put_doubles(ck, "virial", md->last.virial, 6);
    if (!rc) rc = ckpt_put_box(ck, "model/md/box", &md->box);
    if (!rc) rc = ckpt_put_particles(ck, "model/md/atoms", md->p);
    return rc;
}

static int md_model_checkpoint_read(void *self, struct ckpt *ck, struct err *e)
{
    struct md_model *m = self;
    struct md *md = m->md;
    int rc = ckpt_get_long(ck, "step", &md->step);
    if (!rc) rc = ckpt_get_double(ck, "time", &md->time);
    if (!rc) rc = ckpt_get_long(ck, "nrebuilds", &md->nrebuilds);
    if (!rc) rc = ckpt_get_double(ck, "energy", &md->last.energy);
    if (!rc) rc = ckpt_get_doubles(ck, "virial", md->last.virial, 6);
    if (!rc) rc = ckpt_get_box(ck, "model/md/box", &md->box);
    if (!rc) rc = ckpt_get_particles(ck, "model/md/atoms", md->p);
    return rc;
}

/* Ghosts and lists are rebuilt from the stored state at the next force
 * call, in the continuing run as in the restarted one. */
static void md_model_checkpoint_sync(void *self)
{
    struct md_model *m = self;
    m->md->rebuild_next = 1;
}

const struct sim_model_ops sim_model_md = {
    .name = "md",
    .init = md_model_init,
    .pre_force = md_model_pre_force,
    .force = md_model_force,
    .integrate = md_model_integrate,
    .observe = md_model_observe,
    .checkpoint_write = md_model_checkpoint_write,
    .checkpoint_read = md_model_checkpoint_read,
    .checkpoint_sync = md_model_checkpoint_sync,
};
