/*
 * model_handshake: the coupled MD/MPM step of the handshake (Guo & Yang
 * 2005, section 2.2; couple/handshake.h) as engine stages (models.h).
 *
 * One common dt for both sides.  The step of handshake_step, in stages:
 *   pre_force:  region I at t to the MPM as material points (mass,
 *               momentum, virial stress), one MUSL step moves regions II,
 *               III and the rest to t+dt, the MD copies of II and III take
 *               the new positions (displacement coupling); then the MD's
 *               first half kick and drift (the copies are frozen in it);
 *   force:      MD forces at t+dt, with II and III where the MPM put them;
 *   integrate:  the MD's second half kick, the atoms' damping (quasi-static
 *               runs) and the handshake's counters.
 * Per-atom virials are needed at every step (region I's stress for the
 * next MPM step), not only when a snapshot is due.
 *
 * Checkpoint (/model/handshake): the MD's counters, box and atoms in their
 * current order (positions, velocities, forces, per-atom energies and
 * virials, regions and reference sites) as model_md stores them, and the
 * MPM side and the handshake's counters (handshake_checkpoint_write).  No
 * neighbour list, ghost or index list is stored: after every checkpoint
 * both the continuing and the restarted run rebuild the MD lists at the
 * next force call, locate the points afresh and re-index region I and the
 * copies at the next step (checkpoint_sync).
 *
 * On MPI bricks (the bar case types under mpirun, docs/parallel.md) the
 * atoms and copies, and the material points, are written as model_md
 * writes its atoms: rank 0 lays out the datasets for every rank's
 * particles and points (counted by checkpoint_collect), each rank writes
 * its own rows (checkpoint_write_part);
 * a read gives each rank its brick's particles (model_md_atoms_read), the
 * sync sends strays to their bricks, so a checkpoint of N ranks restarts
 * on M.
 */
#include "engine/models.h"

#include "couple/handshake.h"

#define HS_GROUP "model/handshake"

/* Forces, per-atom energies and virials at step 0 (as model_md's init):
 * the case's set-up may have left the per-atom arrays of a probe behind
 * (md_check_timestep displaces sample atoms and restores only the forces),
 * and region I hands its virials to the MPM at the first step.  On bricks
 * the probe's samples are rank 0's atoms, so without this the first MPM
 * step would see different leftovers on every rank count. */
static int hs_model_init(void *self, struct sim *s, struct err *e)
{
    struct handshake_model *m = self;
    struct md *md = m->hs->md;
    md->peratom = 1;
    return md_compute_forces(md, e);
}

static int hs_model_pre_force(void *self, struct sim *s, struct err *e)
{
    struct handshake_model *m = self;
    struct md *md = m->hs->md;
    md->peratom = 1;   /* region I hands its virial stress to the MPM every step */
    int rc = handshake_advance_mpm(m->hs, e);
    if (rc)
        return rc;
    md_step_drift(md);
    return 0;
}

static int hs_model_force(void *self, struct sim *s, struct err *e)
{
    struct handshake_model *m = self;
    return md_step_forces(m->hs->md, e);
}

static int hs_model_integrate(void *self, struct sim *s, struct err *e)
{
    struct handshake_model *m = self;
    md_step_kick(m->hs->md);
    handshake_finish_step(m->hs);
    return 0;
}

static void hs_model_observe(void *self, const struct sim *s, struct sim_energy *en)
{
    struct handshake_model *m = self;
    struct handshake_energy he;
    handshake_energy(m->hs, &he);
    en->total = he.total;
    /* loads, damping and the handshake's own losses (short waves it does
     * not carry) change the energy by design: only finiteness is checked */
    en->conserved = 0;
    en->scale = 1;
    en->unit = "eV";
}

static int hs_model_checkpoint_write(void *self, struct ckpt *ck, struct err *e)
{
    struct handshake_model *m = self;
    const struct md *md = m->hs->md;
    int rc = ckpt_put_long(ck, "md_step", md->step);
    if (!rc) rc = ckpt_put_double(ck, "md_time", md->time);
    if (!rc) rc = ckpt_put_long(ck, "nrebuilds", md->nrebuilds);
    if (!rc) rc = ckpt_put_double(ck, "energy", md->last.energy);
    if (!rc) rc = ckpt_put_doubles(ck, "virial", md->last.virial, 6);
    if (!rc) rc = ckpt_put_box(ck, HS_GROUP "/box", &md->box);
    /* bricks (rank 0 writes): the datasets for every rank's atoms, which
     * each rank fills with its own (hs_model_checkpoint_write_part), and
     * so for the material points */
    if (!rc && md->halo)
        rc = ckpt_put_particles_layout(ck, HS_GROUP "/atoms", md->p, m->ck_total);
    else if (!rc)
        rc = ckpt_put_particles(ck, HS_GROUP "/atoms", md->p);
    if (!rc) rc = handshake_checkpoint_write(m->hs, ck, HS_GROUP "/mpm");
    return rc;
}

static int hs_model_checkpoint_collect(void *self, struct err *e)
{
    struct handshake_model *m = self;
    struct md *md = m->hs->md;
    m->ck_offset = m->ck_total = 0;
    int rc = md->halo ? model_checkpoint_rows(md->halo, md->p, &m->ck_offset, &m->ck_total, e) : 0;
    /* bricks: every rank's count of material points (collective) */
    return rc ? rc : handshake_checkpoint_collect(m->hs, e);
}

static int hs_model_checkpoint_write_part(void *self, struct ckpt *ck, struct err *e)
{
    struct handshake_model *m = self;
    struct md *md = m->hs->md;
    int rc = md->halo ? ckpt_put_particles_part(ck, HS_GROUP "/atoms", md->p, m->ck_offset) : 0;
    return rc ? rc : handshake_checkpoint_write_part(m->hs, ck, HS_GROUP "/mpm");
}

static int hs_model_checkpoint_read(void *self, struct ckpt *ck, struct err *e)
{
    struct handshake_model *m = self;
    struct md *md = m->hs->md;
    int rc = ckpt_get_long(ck, "md_step", &md->step);
    if (!rc) rc = ckpt_get_double(ck, "md_time", &md->time);
    if (!rc) rc = ckpt_get_long(ck, "nrebuilds", &md->nrebuilds);
    if (!rc) rc = ckpt_get_double(ck, "energy", &md->last.energy);
    if (!rc) rc = ckpt_get_doubles(ck, "virial", md->last.virial, 6);
    if (!rc) rc = ckpt_get_box(ck, HS_GROUP "/box", &md->box);
    /* bricks: each rank its brick's atoms and copies (model_md's reader) */
    rc = model_md_atoms_read(md, ck, HS_GROUP "/atoms", rc, &m->read_all, e);
    if (!rc) rc = handshake_checkpoint_read(m->hs, ck, HS_GROUP "/mpm");
    return rc;
}

static void hs_model_checkpoint_sync(void *self)
{
    struct handshake_model *m = self;
    struct md *md = m->hs->md;
    md->rebuild_next = 1;
    if (md->halo) {   /* every atom to its brick; an error is reported by the next force call */
        struct err e = {0};
        md->sync_rc = md_decomposed_sync(md, m->read_all, &e);
        m->read_all = 0;
    }
    handshake_checkpoint_sync(m->hs);
}

const struct sim_model_ops sim_model_handshake = {
    .name = "handshake",
    .init = hs_model_init,
    .pre_force = hs_model_pre_force,
    .force = hs_model_force,
    .integrate = hs_model_integrate,
    .observe = hs_model_observe,
    .checkpoint_write = hs_model_checkpoint_write,
    .checkpoint_read = hs_model_checkpoint_read,
    .checkpoint_sync = hs_model_checkpoint_sync,
    .checkpoint_collect = hs_model_checkpoint_collect,
    .checkpoint_write_part = hs_model_checkpoint_write_part,
};
