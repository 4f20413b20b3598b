/* sim: the time loop, divergence check, outputs and checkpoints (sim.h). */
#include "engine/sim.h"
#include "util/wfile.h"

#include "core/parallel.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void sim_init(struct sim *s, struct run *r, long steps, double dt)
{
    memset(s, 0, sizeof *s);
    s->run = r;
    s->steps = steps;
    s->dt = dt;
    s->nphases = 1;
    s->phase[0] = (struct sim_phase){"run", steps};
    s->checkpoint_every = r ? r->out.checkpoint_every : 0;
    s->restarted_from = -1;
}

void sim_init_subrun(struct sim *s, struct run *r, long steps, double dt)
{
    sim_init(s, r, steps, dt);
    s->subrun = 1;
    s->checkpoint_every = 0;
}

static struct timers *sim_timers(struct sim *s)
{
    return s->run ? &s->run->timers : &s->own_timers;
}

int sim_add_model_named(struct sim *s, const struct sim_model_ops *ops, void *self,
                        const char *name, struct err *e)
{
    if (s->nmodels >= SIM_MAX_MODELS)
        return err_set(e, ERR_RUNTIME, "at most %d models in one simulation", SIM_MAX_MODELS);
    /* each model's state has its own checkpoint group */
    for (int k = 0; k < s->nmodels; k++)
        if (strcmp(s->model[k].name, name) == 0)
            return err_set(e, ERR_RUNTIME, "two models named %s in one simulation: give the "
                                           "instances distinct names (sim_add_model_named)",
                           name);
    s->model[s->nmodels++] = (struct sim_model){ops, self, name};
    return 0;
}

int sim_add_model(struct sim *s, const struct sim_model_ops *ops, void *self, struct err *e)
{
    return sim_add_model_named(s, ops, self, ops->name, e);
}

int sim_add_phase(struct sim *s, const char *name, long steps, struct err *e)
{
    if (s->nphases == 1 && strcmp(s->phase[0].name, "run") == 0) {
        s->nphases = 0;   /* the first declared phase replaces the default one */
        s->steps = 0;
    }
    if (s->nphases >= SIM_MAX_PHASES)
        return err_set(e, ERR_RUNTIME, "at most %d phases in one simulation", SIM_MAX_PHASES);
    s->phase[s->nphases++] = (struct sim_phase){name, steps};
    s->steps += steps;
    return 0;
}

int sim_due(const struct sim *s, long every)
{
    return run_due(s->step, s->steps, every);
}

static unsigned due_bits(const struct sim *s)
{
    if (!s->run)
        return (s->step == s->steps || s->stop) ? SIM_DUE_LAST : 0;
    const struct output_settings *o = &s->run->out;
    unsigned due = 0;
    if (sim_due(s, o->thermo_every))
        due |= SIM_DUE_THERMO;
    if (sim_due(s, o->snapshot_every))
        due |= SIM_DUE_SNAPSHOT;
    if (o->xyz_every > 0 && s->step % o->xyz_every == 0)
        due |= SIM_DUE_XYZ;
    if (s->step == s->steps || s->stop)
        due |= SIM_DUE_LAST;
    return due;
}

/* Under MPI a write that failed on one rank (rank 0 writes the files)
 * fails the step on every rank: the others would otherwise go on to the
 * next step's exchanges and wait for a rank that has stopped. */
static int agree(const struct sim *s, int rc, const char *what, struct err *e)
{
    const struct parallel *par = s->run ? s->run->opt.par : NULL;
    if (!par || par->size < 2)
        return rc;
    if (parallel_any(par, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME,
                               "step %ld: stopped: another MPI rank failed to write %s", s->step,
                               what);
    return rc;
}

static int output(struct sim *s, unsigned due, struct err *e)
{
    if (!s->case_ops || !s->case_ops->output || !due)
        return 0;
    timer_start(sim_timers(s), TIMER_OUTPUT);
    int rc = s->case_ops->output(s->case_state, s, due, e);
    timer_stop(sim_timers(s), TIMER_OUTPUT);
    return agree(s, rc, "the output", e);
}

/* Non-finite energy, or a conserving model whose energy ran away. */
static int check_divergence(struct sim *s, struct err *e)
{
    for (int k = 0; k < s->nmodels; k++) {
        const struct sim_model *m = &s->model[k];
        if (!m->ops->observe)
            continue;
        struct sim_energy en = {0};
        m->ops->observe(m->self, s, &en);
        if (!isfinite(en.total)) {
            snprintf(s->diverged, sizeof s->diverged, "non-finite energy at step %ld", s->step);
            return err_set(e, ERR_DIVERGED, "diverged: %s", s->diverged);
        }
        const struct sim_energy *e0 = &s->e0[k];
        if (e0->conserved && e0->limit > 0 && e0->scale > 0) {
            double change = (en.total - e0->total) / e0->scale;
            if (fabs(change) > e0->limit) {
                snprintf(s->diverged, sizeof s->diverged,
                         "total energy changed by %.3g %s at step %ld (limit %s = %g %s): time "
                         "step too large?",
                         change, e0->unit, s->step, e0->limit_key, e0->limit, e0->unit);
                return err_set(e, ERR_DIVERGED, "diverged: %s", s->diverged);
            }
        }
    }
    return 0;
}

/* --- checkpoints ----------------------------------------------------------- */

static void ckpt_name(const struct sim *s, long step, char *out, size_t len)
{
    char name[64];
    snprintf(name, sizeof name, "checkpoint-%010ld.h5", step);
    run_path(s->run, name, out, len);
}

static int write_engine_state(struct sim *s, struct ckpt *ck)
{
    int rc = ckpt_enter(ck, "engine");
    double e0[SIM_MAX_MODELS];
    for (int k = 0; k < s->nmodels; k++)
        e0[k] = s->e0[k].total;
    if (!rc) rc = ckpt_put_long(ck, "step", s->step);
    if (!rc) rc = ckpt_put_double(ck, "time", s->time);
    if (!rc) rc = ckpt_put_double(ck, "dt", s->dt);
    if (!rc) rc = ckpt_put_long(ck, "phase", s->cur_phase);
    if (!rc) rc = ckpt_put_long(ck, "phase_step", s->phase_step);
    if (!rc) rc = ckpt_put_long(ck, "nmodels", s->nmodels);
    if (!rc) rc = ckpt_put_doubles(ck, "initial_energy", e0, s->nmodels);
    return rc;
}

static int read_engine_state(struct sim *s, struct ckpt *ck)
{
    int rc = ckpt_enter(ck, "engine");
    long phase = 0, nmodels = 0;
    double e0[SIM_MAX_MODELS];
    if (!rc) rc = ckpt_get_long(ck, "nmodels", &nmodels);
    if (!rc && nmodels != s->nmodels)
        rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint has %ld models, the case has %d",
                     ck->path, nmodels, s->nmodels);
    if (!rc) rc = ckpt_get_long(ck, "step", &s->step);
    if (!rc) rc = ckpt_get_double(ck, "time", &s->time);
    if (!rc) rc = ckpt_get_double(ck, "dt", &s->dt);
    if (!rc) rc = ckpt_get_long(ck, "phase", &phase);
    if (!rc) rc = ckpt_get_long(ck, "phase_step", &s->phase_step);
    if (!rc) rc = ckpt_get_doubles(ck, "initial_energy", e0, s->nmodels);
    if (!rc && (phase < 0 || phase >= s->nphases || s->step < 0 || s->step > s->steps))
        rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint step %ld / phase %ld do not fit the "
                                       "case's schedule (%ld steps, %d phases)",
                     ck->path, s->step, phase, s->steps, s->nphases);
    s->cur_phase = (int)phase;
    for (int k = 0; !rc && k < s->nmodels; k++)
        s->e0[k].total = e0[k];
    return rc;
}

/* Remove all but the newest `keep` checkpoints of the output directory. */
static void prune_checkpoints(struct sim *s, int keep)
{
    DIR *d = opendir(s->run->opt.out_dir);
    if (!d)
        return;
    long steps[64];
    int n = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL && n < 64) {
        long st;
        char tail[8];
        if (sscanf(de->d_name, "checkpoint-%ld.%7s", &st, tail) == 2 && strcmp(tail, "h5") == 0)
            steps[n++] = st;
    }
    closedir(d);
    for (int i = 0; i < n; i++) {
        int newer = 0;
        for (int j = 0; j < n; j++)
            newer += steps[j] > steps[i];
        if (newer >= keep) {
            char path[4096];
            ckpt_name(s, steps[i], path, sizeof path);
            unlink(path);
        }
    }
}

/* Under MPI, the second phase of a checkpoint: every rank opens the file
 * rank 0 wrote and closed, and each decomposed model writes its own
 * particles into it (collective parallel HDF5, docs/parallel.md). */
static int write_checkpoint_parts(struct sim *s, const char *tmp, struct err *e)
{
    int any = 0;
    for (int k = 0; k < s->nmodels; k++)
        any |= s->model[k].ops->checkpoint_write_part != NULL;
    if (!any)
        return 0;
    struct ckpt ck;
    int rc = ckpt_open_parallel(&ck, tmp, 1, NULL, NULL, e);
    if (rc)
        return rc;
    for (int k = 0; !rc && k < s->nmodels; k++) {
        const struct sim_model *m = &s->model[k];
        if (!m->ops->checkpoint_write_part)
            continue;
        char g[96];
        snprintf(g, sizeof g, "model/%s", m->name);
        rc = ckpt_agree(&ck, ckpt_enter(&ck, g));
        if (!rc)
            rc = ckpt_agree(&ck, m->ops->checkpoint_write_part(m->self, &ck, e));
    }
    int rc2 = ckpt_close(&ck);
    return rc ? rc : rc2;
}

static int write_checkpoint(struct sim *s, struct err *e)
{
    for (int k = 0; k < s->nmodels; k++)
        if (s->model[k].ops->checkpoint_collect) {
            int rc = s->model[k].ops->checkpoint_collect(s->model[k].self, e);
            if (rc)
                return rc;
        }
    const struct parallel *par = s->run->opt.par;
    int parallel = par && par->mpi;   /* a brick model may lay out its particles */
    char path[4096], tmp[4200];
    ckpt_name(s, s->step, path, sizeof path);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    int rc = 0;
    if (s->run->opt.rank == 0) {   /* rank 0 writes the file (the models' own parts later) */
        struct ckpt ck;
        rc = ckpt_create(&ck, tmp, s->run->case_doc, s->run->case_key, s->step, s->time, e);
        if (!rc)
            rc = write_engine_state(s, &ck);
        for (int k = 0; !rc && k < s->nmodels; k++) {
            const struct sim_model *m = &s->model[k];
            if (!m->ops->checkpoint_write)
                continue;
            char g[96];
            snprintf(g, sizeof g, "model/%s", m->name);
            if (!(rc = ckpt_enter(&ck, g)))
                rc = m->ops->checkpoint_write(m->self, &ck, e);
        }
        if (!rc && s->case_ops && s->case_ops->checkpoint_write && !(rc = ckpt_enter(&ck, "case")))
            rc = s->case_ops->checkpoint_write(s->case_state, &ck, e);
        int rc2 = ckpt_close(&ck);
        rc = rc ? rc : rc2;
    }
    if (parallel) {
        rc = agree(s, rc, "a checkpoint", e);
        if (!rc)
            rc = write_checkpoint_parts(s, tmp, e);
    }
    if (s->run->opt.rank != 0)
        return rc;
    if (!rc && wfile_rename(tmp, path) != 0)
        rc = err_set(e, ERR_RUNTIME, "%s: cannot rename checkpoint: %s", tmp, strerror(errno));
    if (rc) {
        unlink(tmp);
        return rc;
    }
    prune_checkpoints(s, 2);
    return 0;
}

static int read_checkpoint(struct sim *s, const char *path, struct err *e)
{
    struct ckpt ck;
    long step = 0;
    /* under MPI every rank reads through MPI-IO (a decomposed model reads
     * its part of the particles collectively) */
    const struct parallel *par = s->run->opt.par;
    int rc = par && par->mpi
                 ? ckpt_open_parallel(&ck, path, 0, s->run->case_key, &step, e)
                 : ckpt_open(&ck, path, s->run->case_key, &step, e);
    if (rc)
        return rc;
    rc = read_engine_state(s, &ck);
    for (int k = 0; !rc && k < s->nmodels; k++) {
        const struct sim_model *m = &s->model[k];
        if (!m->ops->checkpoint_read)
            continue;
        char g[96];
        snprintf(g, sizeof g, "model/%s", m->name);
        if (!(rc = ckpt_enter(&ck, g)))
            rc = m->ops->checkpoint_read(m->self, &ck, e);
    }
    if (!rc && s->case_ops && s->case_ops->checkpoint_read && !(rc = ckpt_enter(&ck, "case")))
        rc = s->case_ops->checkpoint_read(s->case_state, &ck, e);
    ckpt_close(&ck);
    if (rc)
        return rc == ERR_DIVERGED ? ERR_INPUT : rc;
    s->restarted_from = s->step;
    return 0;
}

static void sync_models(struct sim *s)
{
    for (int k = 0; k < s->nmodels; k++)
        if (s->model[k].ops->checkpoint_sync)
            s->model[k].ops->checkpoint_sync(s->model[k].self);
}

static int is_dir(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

int sim_find_checkpoint(const char *path, const char *case_key, char *out, size_t len,
                        struct err *e)
{
    struct stat sb;
    if (stat(path, &sb) != 0)
        return err_set(e, ERR_INPUT, "%s: %s", path, strerror(errno));
    if (!is_dir(path)) {
        struct ckpt ck;
        int rc = ckpt_open(&ck, path, case_key, NULL, e);
        if (rc)
            return rc;
        ckpt_close(&ck);
        snprintf(out, len, "%s", path);
        return 0;
    }
    DIR *d = opendir(path);
    if (!d)
        return err_set(e, ERR_INPUT, "%s: cannot read directory: %s", path, strerror(errno));
    long steps[256];
    int n = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL && n < 256) {
        long st;
        char tail[8];
        if (sscanf(de->d_name, "checkpoint-%ld.%7s", &st, tail) == 2 && strcmp(tail, "h5") == 0)
            steps[n++] = st;
    }
    closedir(d);
    /* newest first; an unreadable newest one (a disk error after the
     * rename) falls back to the one before */
    struct err first = {0};
    for (int tried = 0; tried < n; tried++) {
        int best = -1;
        for (int i = 0; i < n; i++)
            if (steps[i] >= 0 && (best < 0 || steps[i] > steps[best]))
                best = i;
        char file[4096];
        snprintf(file, sizeof file, "%s/checkpoint-%010ld.h5", path, steps[best]);
        steps[best] = -1;
        struct ckpt ck;
        struct err e2 = {0};
        if (ckpt_open(&ck, file, case_key, NULL, &e2) == 0) {
            ckpt_close(&ck);
            snprintf(out, len, "%s", file);
            return 0;
        }
        if (!first.code)
            first = e2;
    }
    if (first.code)
        return err_set(e, ERR_INPUT, "%s: no valid checkpoint (newest: %s)", path, first.msg);
    return err_set(e, ERR_INPUT, "%s: no checkpoint-*.h5 file to restart from", path);
}

/* --- the loop -------------------------------------------------------------- */

static int run_stage(struct sim *s, int which, struct err *e)
{
    for (int k = 0; k < s->nmodels; k++) {
        const struct sim_model_ops *o = s->model[k].ops;
        int (*stage)(void *, struct sim *, struct err *) =
            which == 0 ? o->pre_force : which == 1 ? o->force : which == 2 ? o->integrate
                                                                           : o->post_step;
        if (stage) {
            int rc = stage(s->model[k].self, s, e);
            if (rc)
                return rc;
        }
    }
    return 0;
}

/* Checkpoints need every model to write and read its state. */
static int check_checkpointable(const struct sim *s, struct err *e)
{
    for (int k = 0; k < s->nmodels; k++)
        if (!s->model[k].ops->checkpoint_write || !s->model[k].ops->checkpoint_read)
            return err_set(e, ERR_INPUT,
                           "output.checkpoint_every / --restart: model '%s' of this case cannot "
                           "write checkpoints yet",
                           s->model[k].name);
    return 0;
}

int sim_run(struct sim *s, const char *restart, struct err *e)
{
    static const struct sim_case_ops no_hooks;
    struct run *r = s->run;
    const struct sim_case_ops *co = s->case_ops ? s->case_ops : &no_hooks;
    struct timers *tm = sim_timers(s);
    int rc = 0;
    if (s->checkpoint_every > 0 || restart)
        rc = check_checkpointable(s, e);
    s->peratom = r ? run_due(s->step, s->steps, r->out.snapshot_every) : 0;
    for (int k = 0; k < s->nmodels && !rc; k++)
        if (s->model[k].ops->init)
            rc = s->model[k].ops->init(s->model[k].self, s, e);
    for (int k = 0; k < s->nmodels && !rc; k++)
        if (s->model[k].ops->observe)
            s->model[k].ops->observe(s->model[k].self, s, &s->e0[k]);
    if (!rc && restart) {
        rc = read_checkpoint(s, restart, e);
        if (!rc) {
            sync_models(s);
            run_log(r, "restart: continuing from step %ld (%s)", s->step, restart);
        }
    }
    if (!rc && co->begin)
        rc = co->begin(s->case_state, s, e);
    rc = agree(s, rc, "its output files", e);   /* rank 0 opened them */
    if (!rc && s->restarted_from < 0)
        rc = output(s, due_bits(s), e);
    /* under mpirun every rank runs the loop; rank 0 alone shows it */
    int show = r && !s->subrun && r->opt.progress && !r->opt.quiet && r->opt.rank == 0;
    struct progress quiet_progress;
    struct progress *pr = r && !s->subrun ? &r->progress : &quiet_progress;
    progress_start_at(pr, stderr, s->steps, s->step, s->dt, show);
    timer_start(tm, TIMER_LOOP);
    while (!rc && s->step < s->steps && !s->stop) {
        /* the next phase (phases of 0 steps are passed over) */
        while (s->phase_step >= s->phase[s->cur_phase].steps && s->cur_phase + 1 < s->nphases) {
            s->cur_phase++;
            s->phase_step = 0;
        }
        if (s->phase_step == 0 && co->phase_begin &&
            (rc = co->phase_begin(s->case_state, s, s->cur_phase, e)))
            break;
        /* per-particle energies and stresses only when a snapshot or an
         * XYZ frame is due (they add tallies, never change the forces) */
        s->peratom = r ? run_due(s->step + 1, s->steps, r->out.snapshot_every) ||
                             (r->out.xyz_every > 0 && (s->step + 1) % r->out.xyz_every == 0)
                       : 0;
        if ((rc = run_stage(s, 0, e)) || (rc = run_stage(s, 1, e)) || (rc = run_stage(s, 2, e)) ||
            (rc = run_stage(s, 3, e)))
            break;
        s->step++;
        s->time += s->dt;
        s->phase_step++;
        if ((rc = check_divergence(s, e)))
            break;
        if (co->after_step && (rc = co->after_step(s->case_state, s, e)))
            break;
        if ((rc = output(s, due_bits(s), e)))
            break;
        if (s->checkpoint_every > 0 && s->step % s->checkpoint_every == 0 && s->step < s->steps &&
            !s->stop) {
            timer_start(tm, TIMER_CHECKPOINT);
            rc = agree(s, write_checkpoint(s, e), "a checkpoint", e);
            timer_stop(tm, TIMER_CHECKPOINT);
            if (rc)
                break;
            /* the uninterrupted run continues from the same state a
             * restarted one starts in */
            sync_models(s);
        }
        progress_update(pr, s->step);
        /* testing hook (run_options): kills the run that starts from step 0,
         * not the one that continues it */
        if (r && !s->subrun && s->restarted_from < 0 && r->opt.kill_at_step == s->step)
            raise(SIGKILL);
    }
    timer_stop(tm, TIMER_LOOP);
    progress_finish(pr, s->step);
    if (r && !s->subrun) {
        r->steps_run = s->step - (s->restarted_from > 0 ? s->restarted_from : 0);
        /* beside the metrics, so a restarted run's metrics equal the
         * uninterrupted run's */
        if (s->restarted_from >= 0)
            json_object_set_new(r->result.root, "restarted_from_step",
                                json_integer((json_int_t)s->restarted_from));
    }
    if (co->report) {
        struct err e2 = {0};
        int rc2 = co->report(s->case_state, s, rc, rc ? &e2 : e);
        if (!rc)
            rc = rc2;
    }
    return rc;
}
