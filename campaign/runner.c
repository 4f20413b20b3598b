/* runner: the scheduling loop -- claim, start, wait, record, retry. */
#include "runner.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "progress_view.h"
#include "store.h"
#include "sysinfo.h"
#include "util/mem.h"

enum mem_state { M_QUEUED, M_RUNNING, M_DONE, M_FAILED, M_ELSEWHERE, M_CANCELLED };

struct queue_entry {
    long j;              /* plan index, -1 when taken */
    double retry_at;     /* monotonic: not before */
};

struct slot {
    int busy;
    long j;
    long long run_id;
    int attempt;
    int lost;            /* our lease was taken over: stopped, not to be recorded */
    char run_dir[4096];  /* the attempt's own directory */
};

/* An attempt claimed and built, not yet started. */
struct claimed {
    int has;
    long j;
    long long run_id;
    int attempt;
    double prep_s;       /* time spent claiming and preparing it */
    char run_dir[4096];
    struct launch_spec L;
};

struct run_state {
    const struct study *s;
    const struct plan *p;
    const struct solver *sv;
    const struct runner_options *o;
    struct store store;
    struct backend *b;
    long long study_id;
    long long *job_ids;
    enum mem_state *mem;
    double *dep_check;   /* monotonic time to look at a preparation job held elsewhere */
    signed char *dep_verdict;   /* what that look said: 1 done, -1 failed for good, 0 not yet */
    struct queue_entry *q;
    long qn, qcap, head;
    struct slot *slots;
    int running;
    int stopping, cancelling;
    int detached;        /* SIGHUP with jobs in Slurm: left there for the next runner */
    struct progress_view view;
    struct runner_summary *sum;
    struct err *e;
    int fatal;           /* a database error during recording */
    int infra_streak;    /* infrastructure failures in a row */
    int infra_stop;      /* stopped for them (e says why) */
    double pause_until;  /* monotonic: start nothing before (backoff) */
    long pend_j;         /* the job whose outcome waits for its commit (store.pending) */
    long pend_rows;      /* its metric rows */
    int pend_attempt;
    struct claimed ahead;   /* claimed ahead while every slot is busy (claim_ahead) */
    double *freed_at;       /* monotonic: when a slot's job ended, 0: refilled */
};

static int push(struct run_state *r, long j, double at)
{
    if (r->qn == r->qcap) {
        long cap = r->qcap ? 2 * r->qcap : 1024;
        struct queue_entry *g = mem_realloc(r->q, (size_t)cap * sizeof *g);
        if (!g)
            return -1;
        r->q = g;
        r->qcap = cap;
    }
    r->q[r->qn++] = (struct queue_entry){j, at};
    return 0;
}

static void label(struct run_state *r, long j, char *buf, size_t len)
{
    plan_job_label(r->p, j, buf, len);
}

/* A look at the preparation jobs of j: 1 ready (ask the database), 0 wait,
 * -1 blocked.  A preparation job another runner holds is looked up in the
 * database at most once per poll interval, however many jobs wait for it. */
static int deps_ready(struct run_state *r, long j)
{
    const struct plan_job *pj = &r->p->jobs[j];
    int ready = 1;
    for (int d = 0; d < pj->ndeps; d++) {
        long dj = pj->deps[d];
        enum mem_state m = r->mem[dj];
        if (m == M_ELSEWHERE) {
            double now = sys_mono();
            if (now >= r->dep_check[dj]) {
                r->dep_check[dj] = now + r->o->poll_s;
                enum claim_result v;
                struct err e = {0};
                if (store_job_verdict(&r->store, r->job_ids[dj], &v, &e) == 0)
                    r->dep_verdict[dj] = v == CLAIM_DONE                                   ? 1
                                         : v == CLAIM_EXHAUSTED || v == CLAIM_BLOCKED ? -1
                                                                                      : 0;
            }
            if (r->dep_verdict[dj] < 0)
                return -1;
            if (r->dep_verdict[dj] == 0)
                ready = 0;
            continue;
        }
        if (m == M_FAILED)
            return -1;
        if (m != M_DONE)
            ready = 0;
    }
    return ready;
}

static void final_failure(struct run_state *r, long j, const char *why)
{
    char lab[512];
    label(r, j, lab, sizeof lab);
    r->mem[j] = M_FAILED;
    r->sum->failed++;
    r->view.failed++;
    progress_view_job(&r->view, "failed", r->p->jobs[j].key, lab, 0, why);
}

/* The commit of a deferred outcome failed (store.pending_lost): the job
 * counted as done is not recorded, so it is not done; the runner stops (the
 * caller set fatal with the database's message), the next one runs it. */
static void pending_check(struct run_state *r)
{
    if (!r->store.pending_lost)
        return;
    r->store.pending_lost = 0;
    long j = r->pend_j;
    r->fatal = 1;
    if (r->mem[j] == M_DONE) {
        r->sum->done--;
        r->view.done--;
        r->sum->metric_rows -= r->pend_rows;
        r->mem[j] = M_QUEUED;
    }
    char lab[512];
    label(r, j, lab, sizeof lab);
    progress_view_note(&r->view, "%s (%s), attempt %d: done, but the outcome could not be "
                                 "recorded; the job will run again",
                       r->p->jobs[j].key, lab, r->pend_attempt);
}

/* Commit a deferred outcome (before the runner waits for anything). */
static void pending_flush(struct run_state *r)
{
    if (!r->store.pending)
        return;
    if (store_flush(&r->store, r->e) != 0)
        r->fatal = 1;
    pending_check(r);
}

/* ${prep:KEY} of job j: the directory of the preparation job's recorded
 * done run (the attempt whose files were checked in), looked up when the
 * job starts. */
struct prep_lookup {
    struct run_state *r;
    long j;
    char dir[4096];
};

static const char *prep_dir(void *ctx, const char *key, struct err *e)
{
    struct prep_lookup *pl = ctx;
    struct run_state *r = pl->r;
    const struct plan_job *pj = &r->p->jobs[pl->j];
    for (int d = 0; d < pj->ndeps; d++) {
        long dj = pj->deps[d];
        if (strcmp(r->p->jobs[dj].key, key) != 0)
            continue;
        if (store_done_dir(&r->store, r->job_ids[dj], pl->dir, sizeof pl->dir, e) != 0) {
            err_prefix(e, "preparation job %s: ", key);
            return NULL;
        }
        return pl->dir;
    }
    err_set(e, ERR_RUNTIME, "the case reads preparation job %s, which it does not depend on", key);
    return NULL;
}

/* An attempt at job j failed for reasons outside the job (recorded as
 * such): pause, try the job again, or stop after too many in a row --
 * a full disk or a missing solver fails every job the same way, and
 * charging them would use up their retries in seconds. */
static void infra_failure(struct run_state *r, long j, int attempt, const char *why)
{
    char lab[512];
    label(r, j, lab, sizeof lab);
    r->mem[j] = M_QUEUED;
    r->infra_streak++;
    if (r->infra_streak >= r->o->infra_limit) {
        if (!r->infra_stop) {
            r->infra_stop = 1;
            r->stopping = 1;
            err_set(r->e, ERR_RUNTIME,
                    "stopped after %d infrastructure failures in a row (none was charged to a "
                    "job; fix the cause and run again); the last, %s attempt %d: %s",
                    r->infra_streak, r->p->jobs[j].key, attempt, why);
            progress_view_note(&r->view, "%s", r->e->msg);
        }
        return;
    }
    double backoff = r->o->infra_backoff_s;
    for (int k = 1; k < r->infra_streak; k++)
        backoff *= 2;
    r->pause_until = sys_mono() + backoff;
    progress_view_note(&r->view, "%s (%s), attempt %d: infrastructure failure, not charged to "
                                 "the job: %s; starting nothing for %.1f s",
                       r->p->jobs[j].key, lab, attempt, why, backoff);
    push(r, j, r->pause_until);
}

/* An attempt claimed whose launch could not be built or started: recorded
 * as the attempt's outcome, the environment's failure, not the job's. */
static void start_failed(struct run_state *r, const struct claimed *c)
{
    struct outcome o;
    outcome_start_failure(&o, r->e->msg);
    err_clear(r->e);
    r->mem[c->j] = M_QUEUED;
    int lost;
    int unrecorded = store_finish(&r->store, r->job_ids[c->j], c->run_id, c->run_dir, &o, &lost,
                                  0, r->e) != 0;
    pending_check(r);
    if (unrecorded) {
        r->fatal = 1;
    } else if (lost) {
        r->mem[c->j] = M_ELSEWHERE;
        push(r, c->j, sys_mono() + r->o->poll_s);
    } else {
        infra_failure(r, c->j, c->attempt, o.message);
    }
}

/* Claim queue entry k and build its launch into c (its directory and
 * case.yaml written too when write_dir is set); 1 when c is ready to
 * start, 0 when the entry was dealt with otherwise (not ready, done,
 * leased elsewhere, failed for good, or its start failed and was recorded). */
static int claim_entry(struct run_state *r, long k, struct claimed *c, int write_dir)
{
    struct queue_entry *qe = &r->q[k];
    long j = qe->j;
    const struct plan_job *pj = &r->p->jobs[j];
    double now = sys_mono();
    int dr = deps_ready(r, j);
    if (dr < 0) {
        qe->j = -1;
        final_failure(r, j, "blocked: a preparation job it reads failed");
        return 0;
    }
    if (dr == 0) {
        qe->retry_at = now + 0.05;
        return 0;
    }
    char job_dir[4096];
    snprintf(job_dir, sizeof job_dir, "%s/%s/%s", r->o->runs_root, r->s->name, pj->key);
    double t0 = sys_mono();
    enum claim_result res;
    memset(c, 0, sizeof *c);
    c->j = j;
    /* a job's outcome recorded just before (on_done) is committed with
     * this claim: one transaction per job (store.h) */
    int claimed = store_claim(&r->store, r->job_ids[j], job_dir, &res, &c->run_id, &c->attempt,
                              c->run_dir, sizeof c->run_dir, r->e);
    if (claimed != 0)
        r->fatal = 1;
    pending_check(r);
    if (claimed != 0)
        return 0;
    switch (res) {
    case CLAIM_DONE:
        qe->j = -1;
        if (r->mem[j] != M_DONE) {
            r->sum->done_before += r->mem[j] == M_QUEUED;
            r->sum->done++;
            r->view.done++;
            if (r->mem[j] == M_ELSEWHERE)
                progress_view_tick(&r->view, 1);
        }
        r->mem[j] = M_DONE;
        return 0;
    case CLAIM_LEASED:
    case CLAIM_WAIT:
        if (res == CLAIM_LEASED)
            r->mem[j] = M_ELSEWHERE;
        qe->retry_at = now + r->o->poll_s;
        return 0;
    case CLAIM_BLOCKED:
        qe->j = -1;
        final_failure(r, j, "blocked: a preparation job it reads failed");
        return 0;
    case CLAIM_EXHAUSTED:
        qe->j = -1;
        final_failure(r, j, "not run again: it diverged, crashed the same way twice or failed "
                            "as often as the study allows (cascade retry STUDY to run it anyway)");
        return 0;
    case CLAIM_OK:
        break;
    }
    qe->j = -1;
    struct prep_lookup pl = {r, j, ""};
    /* a job that stopped early (timeout, node failure, killed runner)
     * continues from the newest checkpoint an earlier attempt left */
    char resume[4096];
    int resuming =
        c->attempt > 1 && launch_resume_dir(job_dir, c->attempt, resume, sizeof resume) == 0;
    int rc = launch_build(&c->L, r->s, r->sv, c->run_dir, pj->key, pj->case_json, prep_dir, &pl,
                          resuming ? resume : NULL, r->e);
    if (!rc && write_dir) {
        rc = launch_setup_dir(&c->L, r->e);
        c->L.dir_ready = !rc;
    }
    if (rc) {
        launch_free(&c->L);
        start_failed(r, c);
        return 0;
    }
    c->L.job_id = r->job_ids[j];
    c->L.run_id = c->run_id;
    c->L.plan_index = j;
    c->prep_s = sys_mono() - t0;
    c->has = 1;
    r->mem[j] = M_RUNNING;
    return 1;
}

/* Start a claimed attempt in a free slot; 1 when it started. */
static int launch_claimed(struct run_state *r, struct claimed *c, int slot)
{
    double t0 = sys_mono();
    int rc = r->b->start(r->b, slot, &c->L, r->e);
    launch_free(&c->L);
    c->has = 0;
    if (rc) {
        start_failed(r, c);
        return 0;
    }
    double t1 = sys_mono();
    r->sum->start_s += c->prep_s + (t1 - t0);
    r->sum->started++;
    if (r->freed_at[slot] > 0) {
        r->sum->gap_s += t1 - r->freed_at[slot];
        r->sum->gaps++;
        r->freed_at[slot] = 0;
    }
    struct slot *sl = &r->slots[slot];
    *sl = (struct slot){1, c->j, c->run_id, c->attempt, 0, ""};
    snprintf(sl->run_dir, sizeof sl->run_dir, "%s", c->run_dir);
    r->running++;
    r->view.running = r->running;
    progress_view_tick(&r->view, 1);
    return 1;
}

static int paused(const struct run_state *r, double now)
{
    return r->stopping || r->fatal || now < r->pause_until;
}

static int free_slot(const struct run_state *r)
{
    int slot = 0;
    while (r->slots[slot].busy)
        slot++;
    return slot;
}

static void fill_slots(struct run_state *r)
{
    double now = sys_mono();
    if (paused(r, now))
        return;
    /* after an infrastructure failure one job at a time probes whether the
     * machine works again, rather than every slot failing at once */
    int limit = r->infra_streak > 0 ? 1 : r->b->nslots;
    if (r->ahead.has && r->running < limit)
        launch_claimed(r, &r->ahead, free_slot(r));
    while (r->head < r->qn && r->q[r->head].j < 0)
        r->head++;
    for (long k = r->head; k < r->qn && r->running < limit && !paused(r, now); k++) {
        if (r->q[k].j < 0 || r->q[k].retry_at > now)
            continue;
        struct claimed c;
        if (claim_entry(r, k, &c, 0))
            launch_claimed(r, &c, free_slot(r));
    }
}

/* Every slot busy: claim the next job ahead and write its directory while
 * they run (backend claim_ahead), so that the slot freed first starts it
 * at once.  Its lease is held and renewed like a running job's; a runner
 * killed before starting it leaves it to be reaped and run again. */
static void claim_ahead(struct run_state *r)
{
    double now = sys_mono();
    if (!r->b->claim_ahead || r->ahead.has || r->running < r->b->nslots ||
        r->infra_streak > 0 || paused(r, now))
        return;
    while (r->head < r->qn && r->q[r->head].j < 0)
        r->head++;
    for (long k = r->head; k < r->qn && !r->ahead.has && !paused(r, now); k++)
        if (r->q[k].j >= 0 && r->q[k].retry_at <= now)
            claim_entry(r, k, &r->ahead, 1);
}

/* The runner stops with a job claimed ahead: the claim is undone (its run
 * row and lease deleted, its directory removed), as if it had never been
 * claimed; the next runner runs the job. */
static void release_ahead(struct run_state *r)
{
    if (!r->ahead.has)
        return;
    struct claimed *c = &r->ahead;
    launch_free(&c->L);
    c->has = 0;
    r->mem[c->j] = M_QUEUED;
    struct err e = {0};
    if (store_unclaim(&r->store, r->job_ids[c->j], c->run_id, &e) != 0) {
        progress_view_note(&r->view, "%s: the attempt claimed ahead could not be undone (%s); "
                                     "its lease lapses and the next runner runs the job",
                           r->p->jobs[c->j].key, e.msg);
    } else {
        launch_remove_dir(c->run_dir);
    }
    pending_check(r);
}

static int queue_empty(struct run_state *r)
{
    while (r->head < r->qn && r->q[r->head].j < 0)
        r->head++;
    return r->head >= r->qn;
}

static double next_retry(struct run_state *r)
{
    double t = r->ahead.has ? sys_mono() : -1;   /* ready to start */
    for (long k = r->head; k < r->qn; k++)
        if (r->q[k].j >= 0 && (t < 0 || r->q[k].retry_at < t))
            t = r->q[k].retry_at;
    return t;
}

/* Whether the study allows another attempt after a failure just recorded. */
static int retry_allowed(struct run_state *r, long j)
{
    enum claim_result v;
    struct err e = {0};
    if (store_job_verdict(&r->store, r->job_ids[j], &v, &e) != 0)
        return 0;
    return v == CLAIM_OK || v == CLAIM_WAIT;
}

static void on_done(void *ctx, int slot, struct outcome *o)
{
    struct run_state *r = ctx;
    struct slot done_slot = r->slots[slot], *sl = &done_slot;
    long j = sl->j;
    int lost = 0;
    double t0 = sys_mono();
    r->freed_at[slot] = t0 - o->collect_s;
    r->slots[slot].busy = 0;
    r->running--;
    /* the job claimed ahead starts before this one is recorded: the slot
     * stays empty only for the reap, reading result.json and the start
     * (not after an infrastructure failure, which pauses starting) */
    int early_failed = 0;
    double t_start = 0;   /* that start, counted under "claim and start" */
    if (r->ahead.has && o->failure != FC_INFRA && r->infra_streak == 0 && !paused(r, t0)) {
        early_failed = !launch_claimed(r, &r->ahead, slot);
        if (!early_failed)
            t_start = sys_mono() - t0;
    }
    /* a job that succeeded is committed with the next claim (or the flush
     * before the runner waits): one transaction per job instead of two */
    int defer = o->status == RS_DONE && o->failure == FC_NONE;
    int unrecorded = store_finish(&r->store, r->job_ids[j], sl->run_id, sl->run_dir, o, &lost,
                                  defer, r->e) != 0;
    if (unrecorded)
        r->fatal = 1;
    pending_check(r);   /* an earlier deferred outcome, committed first */
    if (r->store.note[0])
        progress_view_note(&r->view, "%s: %s", r->p->jobs[j].key, r->store.note);
    r->sum->record_s += sys_mono() - t0 - t_start + o->collect_s;
    if (!lost && !unrecorded)
        r->sum->metric_rows += r->store.last_metric_rows;
    r->view.running = r->running;
    r->view.finished_here++;
    char lab[512];
    label(r, j, lab, sizeof lab);
    const char *status = run_status_name(o->status);
    /* an attempt that ran to an outcome of its own shows the machine works */
    if (!lost && !unrecorded && o->failure != FC_INFRA && o->status != RS_CANCELLED &&
        !early_failed)   /* the start just now came after it: its failure counts */
        r->infra_streak = 0;
    if (unrecorded) {
        /* the transaction rolled back: the run is still 'running' under our
         * lease, which the next runner reaps; the job is not done */
        r->mem[j] = M_QUEUED;
        progress_view_note(&r->view, "%s (%s), attempt %d: %s, but the outcome could not be "
                                     "recorded; the job will run again",
                           r->p->jobs[j].key, lab, sl->attempt, status);
    } else if (lost) {
        r->mem[j] = M_ELSEWHERE;
        if (!sl->lost)   /* else drop_lost_leases said so when it stopped the job */
            progress_view_note(&r->view, "%s: our lease expired and another runner took the "
                                         "job; this result is not recorded", r->p->jobs[j].key);
        push(r, j, sys_mono() + r->o->poll_s);
    } else if (o->failure == FC_INFRA) {
        infra_failure(r, j, sl->attempt, o->message);
    } else if (o->status == RS_DONE) {
        r->mem[j] = M_DONE;
        r->sum->done++;
        r->view.done++;
        if (r->store.pending) {
            r->pend_j = j;
            r->pend_rows = r->store.last_metric_rows;
            r->pend_attempt = sl->attempt;
        }
        progress_view_job(&r->view, status, r->p->jobs[j].key, lab, o->wall_s, NULL);
    } else if (o->status == RS_CANCELLED) {
        r->mem[j] = M_CANCELLED;
        r->sum->cancelled++;
        progress_view_job(&r->view, status, r->p->jobs[j].key, lab, o->wall_s, o->message);
    } else if (run_status_retryable(o->status) && !r->stopping && retry_allowed(r, j)) {
        r->mem[j] = M_QUEUED;
        progress_view_note(&r->view, "%s %s (%s), attempt %d: %s; trying again", status,
                           r->p->jobs[j].key, lab, sl->attempt, o->message);
        push(r, j, sys_mono());
    } else {
        r->mem[j] = M_FAILED;
        r->sum->failed++;
        r->view.failed++;
        progress_view_job(&r->view, status, r->p->jobs[j].key, lab, o->wall_s, o->message);
    }
    outcome_free(o);
}

/* A runner frozen past its lease (SIGSTOP, a suspended VM, a long stall)
 * may find on waking that another runner took its jobs over: their solvers
 * are stopped at once and nothing of them is recorded (store_finish finds
 * the lease gone).  They wrote only their own attempt directories. */
static void drop_lost_leases(struct run_state *r)
{
    for (int i = 0; i < r->b->nslots; i++) {
        struct slot *sl = &r->slots[i];
        if (!sl->busy || sl->lost)
            continue;
        int held = 1;
        struct err e = {0};
        if (store_lease_held(&r->store, r->job_ids[sl->j], sl->run_id, &held, &e) != 0) {
            progress_view_note(&r->view, "cannot check the lease of %s: %s",
                               r->p->jobs[sl->j].key, e.msg);
            continue;
        }
        if (held)
            continue;
        sl->lost = 1;
        progress_view_note(&r->view, "%s: our lease expired and another runner took the job; "
                                     "stopping attempt %d, nothing of it is recorded",
                           r->p->jobs[sl->j].key, sl->attempt);
        /* a job in Slurm is the other runner's now: leave it running */
        if (r->b->release)
            r->b->release(r->b, i);
        else
            r->b->cancel(r->b, i);
    }
    struct claimed *c = &r->ahead;
    int held = 1;
    struct err e = {0};
    if (!c->has || store_lease_held(&r->store, r->job_ids[c->j], c->run_id, &held, &e) != 0 ||
        held)
        return;
    /* claimed ahead and taken over before it started: the other runner's */
    launch_free(&c->L);
    c->has = 0;
    r->mem[c->j] = M_ELSEWHERE;
    push(r, c->j, sys_mono() + r->o->poll_s);
    progress_view_note(&r->view, "%s: our lease expired and another runner took the job; "
                                 "attempt %d (claimed, not started) is dropped",
                       r->p->jobs[c->j].key, c->attempt);
}

static void cancel_all(struct run_state *r)
{
    if (r->cancelling)
        return;
    r->cancelling = 1;
    r->stopping = 1;
    progress_view_note(&r->view, "cancelling %d running job%s", r->running,
                       r->running == 1 ? "" : "s");
    for (int i = 0; i < r->b->nslots; i++)
        if (r->slots[i].busy)
            r->b->cancel(r->b, i);
}

static void handle_signal(struct run_state *r, int sig)
{
    if (sig == SIGINT && !r->stopping) {
        r->stopping = 1;
        r->sum->interrupted = sig;
        progress_view_note(&r->view, "interrupted: no new jobs; waiting for %d running job%s "
                                     "(Ctrl-C again cancels them)",
                           r->running, r->running == 1 ? "" : "s");
        return;
    }
    r->sum->interrupted = sig;
    /* logged out: jobs in Slurm outlive the runner; the next `cascade run`
     * adopts them (their leases lapse with this process) */
    if (sig == SIGHUP && r->b->adopt) {
        r->stopping = 1;
        r->detached = 1;
        progress_view_note(&r->view, "hung up: leaving %d job%s in Slurm; 'cascade run' again "
                                     "follows them",
                           r->running, r->running == 1 ? "" : "s");
        return;
    }
    cancel_all(r);
}

/* The backend submitted attempts (Slurm): their ids are recorded before
 * they may start, so a runner that dies finds them again. */
static int on_submitted(void *ctx, int n, const int *slots, const char *const *ids,
                        const char *state, struct err *e)
{
    struct run_state *r = ctx;
    long long *run_ids = malloc((size_t)(n ? n : 1) * sizeof *run_ids);
    if (!run_ids)
        return err_nomem(e, "run ids");
    for (int i = 0; i < n; i++)
        run_ids[i] = r->slots[slots[i]].run_id;
    int rc = store_record_slurm_ids(&r->store, n, run_ids, ids, state, e);
    free(run_ids);
    return rc;
}

struct job_index {
    long long id;
    long j;
};

static int cmp_job_index(const void *a, const void *b)
{
    long long x = ((const struct job_index *)a)->id, y = ((const struct job_index *)b)->id;
    return x < y ? -1 : x > y;
}

/* Attempts an earlier runner submitted to Slurm and left there: followed
 * from where they are, not submitted again.  skip[j] is set for them. */
static int adopt_jobs(struct run_state *r, char *skip)
{
    struct store_adopted *a = NULL;
    int n = 0;
    int rc = store_adopt(&r->store, r->study_id, &a, &n, r->e);
    if (rc || !n) {
        free(a);
        return rc;
    }
    struct job_index *ix = malloc((size_t)r->p->njobs * sizeof *ix);
    if (!ix) {
        free(a);
        return err_nomem(r->e, "job index");
    }
    for (long j = 0; j < r->p->njobs; j++)
        ix[j] = (struct job_index){r->job_ids[j], j};
    qsort(ix, (size_t)r->p->njobs, sizeof *ix, cmp_job_index);
    int slot = 0, adopted = 0;
    for (int i = 0; i < n && !rc; i++) {
        struct job_index key = {a[i].job_id, 0}, *hit;
        hit = bsearch(&key, ix, (size_t)r->p->njobs, sizeof *ix, cmp_job_index);
        if (!hit || skip[hit->j])
            continue;
        while (slot < r->b->nslots && r->slots[slot].busy)
            slot++;
        if (slot == r->b->nslots)
            break;   /* more than the slots: the rest wait for their lease to lapse */
        rc = r->b->adopt(r->b, slot, hit->j, a[i].run_dir, a[i].slurm_id, r->e);
        if (rc)
            break;
        r->slots[slot] = (struct slot){1, hit->j, a[i].run_id, a[i].attempt, 0, ""};
        snprintf(r->slots[slot].run_dir, sizeof r->slots[slot].run_dir, "%s", a[i].run_dir);
        r->mem[hit->j] = M_RUNNING;
        r->running++;
        skip[hit->j] = 1;
        adopted++;
    }
    if (adopted)
        progress_view_note(&r->view, "%d job%s already in Slurm (submitted by a runner that is "
                                     "gone) followed from where they are",
                           adopted, adopted == 1 ? "" : "s");
    free(ix);
    free(a);
    return rc;
}

int runner_run(const struct study *s, const struct plan *p, const struct solver *sv, sqlite3 *db,
               struct backend *b, const struct runner_options *o, struct runner_summary *sum,
               struct err *e)
{
    memset(sum, 0, sizeof *sum);
    sum->total = p->njobs;
    struct run_state r;
    memset(&r, 0, sizeof r);
    r.s = s;
    r.p = p;
    r.sv = sv;
    r.o = o;
    r.b = b;
    r.sum = sum;
    r.e = e;
    int rc = store_init(&r.store, db, s, sv, o->lease_s, e);
    if (rc)
        return rc;
    r.job_ids = mem_calloc((size_t)p->njobs, sizeof *r.job_ids);
    r.mem = mem_calloc((size_t)p->njobs, sizeof *r.mem);
    r.dep_check = mem_calloc((size_t)p->njobs, sizeof *r.dep_check);
    r.dep_verdict = mem_calloc((size_t)p->njobs, sizeof *r.dep_verdict);
    r.slots = mem_calloc((size_t)b->nslots, sizeof *r.slots);
    r.freed_at = mem_calloc((size_t)b->nslots, sizeof *r.freed_at);
    if (!r.job_ids || !r.mem || !r.dep_check || !r.dep_verdict || !r.slots || !r.freed_at)
        rc = err_nomem(e, "runner");
    if (!rc)
        rc = store_register(&r.store, s, p, &r.study_id, r.job_ids, e);
    int reaped = 0;
    char *adopted = calloc((size_t)(p->njobs ? p->njobs : 1), 1);
    if (!rc && !adopted)
        rc = err_nomem(e, "runner");
    progress_view_init(&r.view, o->log, o->quiet, p->njobs);
    if (!rc && b->adopt) {
        b->submitted = on_submitted;
        b->submitted_ctx = &r;
        rc = adopt_jobs(&r, adopted);
    } else if (!rc) {
        /* attempts left in Slurm would run a second time here */
        int orphans = 0;
        rc = store_slurm_orphans(&r.store, r.study_id, &orphans, e);
        if (!rc && orphans)
            rc = err_set(e, ERR_INPUT,
                         "%d attempt%s of study %s %s in Slurm with no runner following them: "
                         "run it with --backend slurm (which adopts them) or 'cascade cancel "
                         "%s' first",
                         orphans, orphans == 1 ? "" : "s", s->name, orphans == 1 ? "is" : "are",
                         s->name);
    }
    if (!rc)
        rc = store_reap(&r.store, &reaped, e);
    for (long j = 0; j < p->njobs && !rc; j++)
        if (!adopted[j] && push(&r, j, 0) != 0)
            rc = err_nomem(e, "queue");
    free(adopted);
    if (rc) {
        sum->not_run = sum->total;   /* the summary says so, not "0 done, 0 failed" */
        store_fini(&r.store);
        free(r.job_ids);
        free(r.mem);
        free(r.dep_check);
        free(r.dep_verdict);
        free(r.slots);
        free(r.freed_at);
        free(r.q);
        return rc;
    }
    r.view.running = r.running;
    if (reaped)
        progress_view_note(&r.view, "%d job%s left running by a runner that is gone will run again",
                           reaped, reaped == 1 ? "" : "s");
    progress_view_note(&r.view, "study %s: %ld job%s, %d slot%s, solver %s (%s)", s->name,
                       p->njobs, p->njobs == 1 ? "" : "s", b->nslots, b->nslots == 1 ? "" : "s",
                       sv->version, sv->git);
    double next_beat = sys_mono() + o->lease_s / 3.0;
    for (;;) {
        fill_slots(&r);
        claim_ahead(&r);
        pending_flush(&r);
        if (r.fatal && r.running == 0)
            break;
        if (r.running == 0 && (r.stopping || (queue_empty(&r) && !r.ahead.has)))
            break;
        if (r.detached)
            break;
        double now = sys_mono(), wait = 0.5;
        if (r.running == 0) {
            double t = next_retry(&r);
            if (t >= 0 && t < r.pause_until)
                t = r.pause_until;
            wait = t < 0 ? 0.1 : t - now;
            if (wait > 1.0)
                wait = 1.0;
        }
        if (next_beat - now < wait)
            wait = next_beat - now;
        if (wait < 0)
            wait = 0;
        int sig = b->wait(b, wait, on_done, &r);
        if (sig)
            handle_signal(&r, sig);
        if (r.fatal)
            cancel_all(&r);
        if (sys_mono() >= next_beat) {
            struct err he = {0};
            if (store_heartbeat(&r.store, &he) != 0)
                progress_view_note(&r.view, "heartbeat failed: %s", he.msg);
            else
                drop_lost_leases(&r);
            next_beat = sys_mono() + o->lease_s / 3.0;
        }
        progress_view_tick(&r.view, 0);
    }
    release_ahead(&r);
    pending_flush(&r);
    progress_view_finish(&r.view);
    if (sum->started)
        progress_view_note(&r.view,
                           "runner time per job: %.2f ms (claim and start %.2f ms, read and "
                           "record %.2f ms); %ld metric rows recorded in %.3f s",
                           1e3 * (sum->start_s + sum->record_s) / (double)sum->started,
                           1e3 * sum->start_s / (double)sum->started,
                           1e3 * sum->record_s / (double)sum->started, sum->metric_rows,
                           sum->record_s);
    if (sum->gaps)
        progress_view_note(&r.view,
                           "slot idle between jobs: %.2f ms (from a job's exit to the next "
                           "one's start, over %ld starts)",
                           1e3 * sum->gap_s / (double)sum->gaps, sum->gaps);
    sum->not_run = sum->total - sum->done - sum->failed;
    store_fini(&r.store);
    free(r.job_ids);
    free(r.mem);
    free(r.dep_check);
    free(r.dep_verdict);
    free(r.slots);
    free(r.freed_at);
    free(r.q);
    return r.fatal || r.infra_stop ? ERR_RUNTIME : 0;
}
