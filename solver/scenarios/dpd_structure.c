/* dpd_structure: CNA of the DPD particles at the coarse lattice constant
 * (Chen et al. 2014, Fig. 4). */
#include "scenarios/dpd_structure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"

int dpd_structure_read(struct cfg_obj *root, struct dpd_structure *s)
{
    memset(s, 0, sizeof *s);
    s->field = -1;
    s->classified_step = -1;
    struct cfg_obj ao, so;
    int ref, mode, rc;
    /* lattice_constant 0 means the parameter file's, which a shallow read
     * does not load: so not structure_params_read, which needs a value */
    if ((rc = cfg_section(root, "analysis", &ao)) || (rc = cfg_section(&ao, "structure", &so)) ||
        (rc = cfg_enum(&so, "reference", "fcc", structure_ref_names, &ref)) ||
        (rc = cfg_enum(&so, "method", "fixed", cna_mode_names, &mode)) ||
        (rc = cfg_real(&so, "lattice_constant", 0.0, CFG_GE(0), &s->sp.a)) ||
        (rc = cfg_real(&so, "cutoff", 0.0, CFG_GE(0), &s->sp.cutoff)) ||
        (rc = cfg_real(&so, "surface_offset", 0.15, CFG_RANGE(0.01, 0.5), &s->sp.surface_offset)) ||
        (rc = cfg_close(&so)))
        return rc;
    s->sp.ref = (enum structure_ref)ref;
    s->sp.mode = (enum cna_mode)mode;
    return cfg_close(&ao);
}

int dpd_structure_attach(struct dpd_structure *s, struct dpd *d, double a, uint32_t exclude,
                         int nthreads, struct err *e)
{
    if (!(s->sp.a > 0) && !(s->sp.cutoff > 0))
        s->sp.a = a;
    s->sp.nthreads = nthreads;
    s->exclude = exclude;
    int rc = structure_params_resolve(&s->sp, e);
    if (rc)
        return rc;
    s->field = particles_add_field(d->p, "structure", 1, 0, e);
    return s->field < 0 ? ERR_RUNTIME : 0;
}

/* On bricks: the classes of the owned particles from them and their
 * ghosts (the DPD halo reaches the list cutoff + skin, beyond the CNA's
 * reach; a ghost's position is its owner's, so every owned particle sees
 * the neighbours of a serial run), with an open box (the ghosts carry the
 * periodic images). */
static int classify_bricks(struct dpd_structure *s, struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    double reach = structure_range(&s->sp), shell = fmax(d->prm.sc.rc, d->set.cutoff);
    if (!(reach <= shell))
        return err_set(e, ERR_INPUT, "analysis.structure: its reach %g Å exceeds the DPD "
                                     "ghost shell %g Å of the brick decomposition",
                       reach, shell);
    struct box open = d->box;
    for (int k = 0; k < 3; k++)
        open.bc[k] = BOUNDARY_FREE;
    return structure_classify(&s->sp, p->x, p->n_owned + p->n_ghost, &open, &s->fr, s->cls, e);
}

int dpd_structure_classify(struct dpd_structure *s, struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    int n = p->n_owned, ntot = p->halo ? p->n_owned + p->n_ghost : n;
    int rc = 0;
    if (ntot > s->cap) {
        int *c = realloc(s->cls, (size_t)ntot * sizeof *c);
        if (c) {
            s->cls = c;
            s->cap = ntot;
        } else {
            rc = err_nomem(e, "structure classes");
        }
    }
    unsigned char *sel = rc ? NULL : malloc((size_t)(n ? n : 1));
    if (!rc && !sel)
        rc = err_nomem(e, "structure selection");
    if (!rc)
        rc = p->halo ? classify_bricks(s, d, e)
                     : structure_classify_particles(&s->sp, p, &d->box, &s->fr, s->cls, e);
    if (p->halo)   /* no rank waits in the sum below for a failed one */
        rc = halo_agree(p->halo, rc, e);
    if (!rc) {
        double *f = particles_field(p, s->field);
        for (int i = 0; i < n; i++) {
            f[i] = s->cls[i];
            sel[i] = (unsigned char)!(p->mask[i] & s->exclude);
        }
        s->counted = structure_count(s->cls, n, sel, s->counts);
        if (p->halo) {   /* the counts of every rank's particles */
            double sum[STRUCT_NCLASSES + 1];
            for (int k = 0; k < STRUCT_NCLASSES; k++)
                sum[k] = (double)s->counts[k];
            sum[STRUCT_NCLASSES] = (double)s->counted;
            halo_sum(p->halo, sum, STRUCT_NCLASSES + 1);
            for (int k = 0; k < STRUCT_NCLASSES; k++)
                s->counts[k] = lround(sum[k]);
            s->counted = lround(sum[STRUCT_NCLASSES]);
        }
        if (s->classified_step < 0)
            memcpy(s->start, s->counts, sizeof s->start);
        s->classified_step = d->step;
    }
    free(sel);
    return rc;
}

int dpd_structure_before_output(struct dpd_structure *s, struct run *run, struct dpd *d,
                                long total_steps, struct err *e)
{
    /* bricks: every rank writes the snapshot (only rank 0 holds the file) */
    int h5 = d->p->halo ? run->out.hdf5 : run->h5_open;
    if (!h5 || !run_due(d->step, total_steps, run->out.snapshot_every) ||
        s->classified_step == d->step)
        return 0;
    timer_start(&run->timers, TIMER_ANALYSIS);
    int rc = dpd_structure_classify(s, d, e);
    timer_stop(&run->timers, TIMER_ANALYSIS);
    return rc;
}

int dpd_structure_finish(struct dpd_structure *s, struct run *run, struct dpd *d, struct err *e)
{
    int rc = 0;
    if (s->classified_step != d->step) {
        timer_start(&run->timers, TIMER_ANALYSIS);
        rc = dpd_structure_classify(s, d, e);
        timer_stop(&run->timers, TIMER_ANALYSIS);
    }
    if (rc)
        return rc;
    struct result *r = &run->result;
    long fcc = s->counts[STRUCT_FCC], hcp = s->counts[STRUCT_HCP];
    result_metric(r, "cna_fcc", (double)fcc, "1");
    result_metric(r, "cna_hcp", (double)hcp, "1");
    result_metric(r, "cna_other", (double)(s->counted - fcc - hcp), "1");
    result_metric(r, "cna_surface", (double)s->counts[STRUCT_SURFACE], "1");
    result_metric(r, "cna_fcc_start", (double)s->start[STRUCT_FCC], "1");
    result_metric(r, "cna_hcp_start", (double)s->start[STRUCT_HCP], "1");
    result_metric(r, "cna_fcc_fraction", s->counted ? (double)fcc / (double)s->counted : 0.0, "1");
    result_metric(r, "cna_cutoff", s->sp.cutoff, "Å");
    run_log(run, "CNA at a = %.4g Å (cutoff %.4g Å) of %ld particles: fcc %ld, hcp %ld, other %ld",
            s->sp.a, s->sp.cutoff, s->counted, fcc, hcp, s->counted - fcc - hcp);
    return 0;
}

int dpd_structure_checkpoint_write(const struct dpd_structure *s, struct ckpt *ck)
{
    int64_t v[2 * STRUCT_NCLASSES + 2];
    for (int k = 0; k < STRUCT_NCLASSES; k++) {
        v[k] = s->counts[k];
        v[STRUCT_NCLASSES + k] = s->start[k];
    }
    v[2 * STRUCT_NCLASSES] = s->counted;
    v[2 * STRUCT_NCLASSES + 1] = s->classified_step;
    return ckpt_put_i64(ck, "structure_counts", v, 2 * STRUCT_NCLASSES + 2);
}

int dpd_structure_checkpoint_read(struct dpd_structure *s, struct ckpt *ck)
{
    int64_t v[2 * STRUCT_NCLASSES + 2];
    int rc = ckpt_get_i64(ck, "structure_counts", v, 2 * STRUCT_NCLASSES + 2);
    if (rc)
        return rc;
    for (int k = 0; k < STRUCT_NCLASSES; k++) {
        s->counts[k] = (long)v[k];
        s->start[k] = (long)v[STRUCT_NCLASSES + k];
    }
    s->counted = (long)v[2 * STRUCT_NCLASSES];
    s->classified_step = (long)v[2 * STRUCT_NCLASSES + 1];
    return 0;
}

void dpd_structure_free(struct dpd_structure *s)
{
    frame_free(&s->fr);
    free(s->cls);
    s->cls = NULL;
    s->cap = 0;
}
