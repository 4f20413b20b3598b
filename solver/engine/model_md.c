/* model_md: molecular dynamics as engine stages (models.h). */
#include "engine/models.h"

#include "core/halo.h"
#include "core/parallel.h"

#include <stdlib.h>
#include <string.h>

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
    long n = md_natoms(md);
    en->scale = n > 0 ? (double)n : 1;
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
    /* bricks: the datasets for every rank's atoms; each rank writes its
     * own (md_model_checkpoint_write_part) */
    if (!rc && md->halo)
        rc = ckpt_put_particles_layout(ck, "model/md/atoms", md->p, m->ck_total);
    else if (!rc)
        rc = ckpt_put_particles(ck, "model/md/atoms", md->p);
    return rc;
}

static int md_model_checkpoint_write_part(void *self, struct ckpt *ck, struct err *e)
{
    struct md_model *m = self;
    return m->md->halo ? ckpt_put_particles_part(ck, "model/md/atoms", m->md->p, m->ck_offset)
                       : 0;
}

int model_md_atoms_read(struct md *md, struct ckpt *ck, const char *group, int rc,
                        int *read_all, struct err *e)
{
    *read_all = 0;
    if (md->halo && !ck->par) {   /* bricks: each rank reads its brick's atoms */
        rc = model_particles_read_brick(md->halo, &md->box, ck, group, NULL, md->p, rc, e);
        *read_all = !rc;   /* the sync migrates strays */
        return rc;
    }
    if (md->halo) {   /* a collective file: an even share of the stored rows */
        const struct parallel *par = md->halo->dc.par;
        if (!rc)
            decomp_set_box(&md->halo->dc, &md->box);
        if (!rc)
            rc = ckpt_get_particles_part(ck, group, md->p, par->rank, par->size);
        /* counted over the ranks; the sync migrates them to their bricks */
        rc = halo_adopt(md->halo, md->p, rc, e);
        return rc ? rc : model_ids_unique_over_ranks(md->halo, md->p, ck, group, e);
    }
    if (!rc) rc = ckpt_get_particles(ck, group, md->p);
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
    return model_md_atoms_read(md, ck, "model/md/atoms", rc, &m->read_all, e);
}

/* Bricks: this rank's rows of the checkpoint's atoms follow those of
 * the lower ranks. */
static int md_model_checkpoint_collect(void *self, struct err *e)
{
    struct md_model *m = self;
    m->ck_offset = m->ck_total = 0;
    if (!m->md->halo)
        return 0;
    return model_checkpoint_rows(m->md->halo, m->md->p, &m->ck_offset, &m->ck_total, e);
}

/* Ghosts and lists are rebuilt from the stored state at the next force
 * call, in the continuing run as in the restarted one. */
static void md_model_checkpoint_sync(void *self)
{
    struct md_model *m = self;
    m->md->rebuild_next = 1;
    if (m->md->halo) {   /* an error is reported by the next force call */
        struct err e = {0};
        m->md->sync_rc = md_decomposed_sync(m->md, m->read_all, &e);
        m->read_all = 0;
    }
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
    .checkpoint_collect = md_model_checkpoint_collect,
    .checkpoint_write_part = md_model_checkpoint_write_part,
};
