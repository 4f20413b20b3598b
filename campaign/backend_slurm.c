/* backend_slurm: job attempts as Slurm array tasks (see backend_slurm.h). */
#include "backend_slurm.h"

#include <errno.h>
#include <pwd.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "slurm_script.h"
#include "slurm_spec.h"
#include "slurm_state.h"
#include "study.h"
#include "sysinfo.h"

enum sl_state { SL_FREE, SL_STARTED, SL_SUBMITTED, SL_REPORT };
enum sl_report { REP_CANCELLED, REP_SUBMIT_FAILED, REP_FORGOTTEN };

struct sl_slot {
    enum sl_state st;
    long j;
    long long seq;           /* start order */
    char run_dir[4096];
    char id[32];             /* "ARRAY_TASK" once submitted */
    int cancel_req, cancel_sent, forget;
    int launch_failed;       /* Slurm held it after a failed launch; we cancelled it */
    char launch_node[64];    /* where that launch failed, for the message */
    int missing;             /* polls in a row it was not in squeue's answer */
    int seen_running;        /* RUNNING was recorded */
    int no_result;           /* polls it was COMPLETED without a result.json yet */
    enum sl_report report;
    char msg[512];
};

struct slurm_backend {
    struct slurm_cli cli;
    const struct study *s;
    const struct plan *p;
    struct slurm_job_res *groups;  /* distinct resources */
    int ngroups;
    int *group_of;                 /* per plan job */
    struct sl_slot *slots;
    int nslots;
    long long seq;
    long max_array;                /* tasks per array (MaxArraySize) */
    char job_name[STUDY_NAME_MAX + 16];
    char runs_root[4096];
    char slurm_dir[4096 + STUDY_NAME_MAX + 16];
    char last_array[32];           /* the array the next one is chained after */
    double next_poll;
    long polls, squeue_failures;
    int narrays;
    int accounting;                /* sacct answers (AccountingStorageType not none) */
    long nsubmitted;               /* attempts submitted */
    int arrays_submitted;
    double submit_s;               /* time submitting (array script, sbatch, ids, release) */
    long poll_calls;               /* client calls made while polling */
};

void backend_slurm_report(const struct backend *b, FILE *out)
{
    const struct slurm_backend *x = b->impl;
    if (!x->nsubmitted && !x->polls)
        return;
    fprintf(out,
            "[cascade] slurm: %ld attempt%s submitted in %d array%s, %.3f ms per attempt "
            "(array script, sbatch, recording the ids, release); %ld poll%s, "
            "%.2f client calls per poll (squeue %ld, scontrol %ld, sacct %ld in all)\n",
            x->nsubmitted, x->nsubmitted == 1 ? "" : "s", x->arrays_submitted,
            x->arrays_submitted == 1 ? "" : "s",
            x->nsubmitted ? 1e3 * x->submit_s / (double)x->nsubmitted : 0.0, x->polls,
            x->polls == 1 ? "" : "s", x->polls ? (double)x->poll_calls / (double)x->polls : 0.0,
            x->cli.calls[SP_SQUEUE], x->cli.calls[SP_SCONTROL], x->cli.calls[SP_SACCT]);
}

/* --- the cluster's limits and partitions -------------------------------------- */

static const char *conf_value(const char *text, const char *key, char *out, size_t len)
{
    out[0] = '\0';
    size_t kl = strlen(key);
    for (const char *l = text; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        if (strncmp(l, key, kl) != 0 || (l[kl] != ' ' && l[kl] != '='))
            continue;
        const char *eq = strchr(l, '=');
        if (!eq)
            continue;
        eq++;
        while (*eq == ' ')
            eq++;
        size_t n = strcspn(eq, "\n");
        snprintf(out, len, "%.*s", (int)n, eq);
        return out;
    }
    return NULL;
}

struct partition {
    char name[128];
    long max_time_s;     /* -1: unlimited */
    long max_nodes;      /* -1: unlimited */
    int is_default;
};

static const char *token(const char *line, const char *key, char *out, size_t len)
{
    char pat[64];
    snprintf(pat, sizeof pat, "%s=", key);
    for (const char *p = line; (p = strstr(p, pat)); p++) {
        if (p != line && p[-1] != ' ')
            continue;
        p += strlen(pat);
        size_t n = strcspn(p, " \n");
        snprintf(out, len, "%.*s", (int)n, p);
        return out;
    }
    out[0] = '\0';
    return NULL;
}

static int read_partitions(struct slurm_backend *x, struct partition **out, int *n,
                           struct err *e)
{
    const char *args[] = {"show", "partition", "-o", NULL};
    char *text, why[512];
    int status;
    *out = NULL;
    *n = 0;
    int rc = slurm_cli_run(&x->cli, SP_SCONTROL, args, &text, why, sizeof why, &status, e);
    if (rc)
        return rc;
    if (status != 0) {
        free(text);
        return err_set(e, ERR_RUNTIME, "scontrol show partition failed (exit %d): %s", status,
                       why);
    }
    int cap = 0;
    for (char *l = text; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        char v[128];
        if (!token(l, "PartitionName", v, sizeof v))
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 8;
            struct partition *g = realloc(*out, (size_t)cap * sizeof *g);
            if (!g) {
                free(text);
                return err_nomem(e, "partitions");
            }
            *out = g;
        }
        struct partition *pt = &(*out)[(*n)++];
        snprintf(pt->name, sizeof pt->name, "%s", v);
        token(l, "MaxTime", v, sizeof v);
        pt->max_time_s = strcmp(v, "UNLIMITED") == 0 || !v[0] ? -1 : slurm_time_seconds(v);
        token(l, "MaxNodes", v, sizeof v);
        pt->max_nodes = strcmp(v, "UNLIMITED") == 0 || !v[0] ? -1 : atol(v);
        token(l, "Default", v, sizeof v);
        pt->is_default = strcmp(v, "YES") == 0;
    }
    free(text);
    return 0;
}

static void where_of(const struct slurm_backend *x, const struct slurm_job_res *jr,
                     enum slurm_res r, char *out, size_t len)
{
    if (jr->where[r] && strcmp(jr->where[r], "timeout") == 0) {
        char loc[STUDY_PATH_MAX + 32];
        study_where(x->s, "timeout", loc, sizeof loc);
        snprintf(out, len, "%s: timeout", loc);
    } else {
        snprintf(out, len, "%s", jr->where[r] && jr->where[r][0] ? jr->where[r] : x->s->file);
    }
}

static long first_job_of(const struct slurm_backend *x, int g)
{
    for (long j = 0; j < x->p->njobs; j++)
        if (x->group_of[j] == g)
            return j;
    return 0;
}

/* The resources of group g against the partitions, then sbatch --test-only. */
static int check_group(struct slurm_backend *x, int g, const struct partition *pt, int npt,
                       struct err *e)
{
    const struct slurm_job_res *jr = &x->groups[g];
    char lab[512], where[512];
    plan_job_label(x->p, first_job_of(x, g), lab, sizeof lab);
    char names[SLURM_VALUE_MAX];
    snprintf(names, sizeof names, "%s", jr->v[SR_PARTITION]);
    if (!names[0]) {
        for (int i = 0; i < npt; i++)
            if (pt[i].is_default)
                snprintf(names, sizeof names, "%s", pt[i].name);
        if (!names[0])
            return err_set(e, ERR_INPUT, "%s: no slurm.partition given and the cluster has no "
                                         "default partition",
                           x->s->file);
    }
    char *save = NULL;
    for (char *n = strtok_r(names, ",", &save); n; n = strtok_r(NULL, ",", &save)) {
        int k = 0;
        while (k < npt && strcmp(pt[k].name, n) != 0)
            k++;
        where_of(x, jr, SR_PARTITION, where, sizeof where);
        if (k == npt) {
            char known[1024] = "";
            for (int i = 0; i < npt; i++)
                snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s",
                         i ? ", " : "", pt[i].name);
            return err_set(e, ERR_INPUT, "%s: '%s' is not a partition of this cluster (it has: "
                                         "%s); nothing was submitted",
                           where, n, known);
        }
        if (jr->time_s > 0 && pt[k].max_time_s >= 0 && jr->time_s > pt[k].max_time_s) {
            char lim[32];
            slurm_time_format(pt[k].max_time_s, lim, sizeof lim);
            where_of(x, jr, SR_TIME, where, sizeof where);
            return err_set(e, ERR_INPUT, "%s: time limit %s (job %s) is over the MaxTime of "
                                         "partition %s, %s; nothing was submitted",
                           where, jr->v[SR_TIME], lab, pt[k].name, lim);
        }
        long nodes = jr->v[SR_NODES][0] ? atol(jr->v[SR_NODES]) : 1;
        if (pt[k].max_nodes >= 0 && nodes > pt[k].max_nodes) {
            where_of(x, jr, SR_NODES, where, sizeof where);
            return err_set(e, ERR_INPUT, "%s: %ld nodes (job %s) is over the MaxNodes of "
                                         "partition %s, %ld; nothing was submitted",
                           where, nodes, lab, pt[k].name, pt[k].max_nodes);
        }
    }
    /* what only the controller knows (accounts, QOS, memory, constraints) */
    char opts[SR_COUNT + SLURM_EXTRA_MAX][160];
    int no = slurm_res_args(jr, &x->s->slurm, opts, SR_COUNT + SLURM_EXTRA_MAX);
    const char *args[SR_COUNT + SLURM_EXTRA_MAX + 8];
    int na = 0;
    args[na++] = "--test-only";
    args[na++] = "--output=/dev/null";
    for (int i = 0; i < no; i++)
        args[na++] = opts[i];
    args[na++] = "--wrap=true";
    args[na] = NULL;
    char *out, why[1024];
    int status;
    int rc = slurm_cli_run(&x->cli, SP_SBATCH, args, &out, why, sizeof why, &status, e);
    if (rc)
        return rc;
    free(out);
    if (status != 0)
        return err_set(e, ERR_INPUT, "%s: sbatch refuses the resources of job %s: %s; nothing "
                                     "was submitted",
                       x->s->file, lab, why);
    return 0;
}

static int read_limits(struct slurm_backend *x, long *max_submit, struct err *e)
{
    const char *args[] = {"show", "config", NULL};
    char *text, why[512], v[128];
    int status;
    int rc = slurm_cli_run(&x->cli, SP_SCONTROL, args, &text, why, sizeof why, &status, e);
    if (rc)
        return rc;
    if (status != 0) {
        free(text);
        return err_set(e, ERR_RUNTIME, "cannot reach Slurm: scontrol show config (exit %d): %s",
                       status, why);
    }
    x->max_array = conf_value(text, "MaxArraySize", v, sizeof v) ? atol(v) : 1001;
    if (x->max_array < 1)
        x->max_array = 1;
    long max_jobs = conf_value(text, "MaxJobCount", v, sizeof v) ? atol(v) : 10000;
    int accounting = conf_value(text, "AccountingStorageType", v, sizeof v) &&
                     strstr(v, "none") == NULL;
    free(text);
    x->accounting = accounting;
    *max_submit = max_jobs > 0 ? max_jobs : 10000;
    if (accounting) {
        /* the user's association limit, when accounting knows one */
        struct passwd *pw = getpwuid(getuid());
        char user[160];
        snprintf(user, sizeof user, "user=%s", pw ? pw->pw_name : "root");
        const char *a2[] = {"-nP", "show", "assoc", "where", user, "format=MaxSubmitJobs", NULL};
        struct err ae = {0};
        if (slurm_cli_run(&x->cli, SP_SACCTMGR, a2, &text, why, sizeof why, &status, &ae) == 0) {
            for (char *l = text; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
                long m = atol(l);
                if (m > 0 && m < *max_submit)
                    *max_submit = m;
            }
            free(text);
        }
    }
    return 0;
}

/* --- start, submit ---------------------------------------------------------------- */

static int sl_start(struct backend *b, int slot, const struct launch_spec *L, struct err *e)
{
    struct slurm_backend *x = b->impl;
    struct sl_slot *sl = &x->slots[slot];
    int rc = launch_setup_dir(L, e);
    if (rc)
        return rc;
    const char *base = strrchr(L->run_dir, '/');
    int attempt = base && strncmp(base + 1, "attempt-", 8) == 0 ? atoi(base + 9) : 1;
    char script[4096 + 16];
    snprintf(script, sizeof script, "%s/job.sbatch", L->run_dir);
    struct slurm_job_script js = {x->s->name, x->p->jobs[L->plan_index].key, x->job_name, attempt,
                                  L, &x->groups[x->group_of[L->plan_index]], &x->s->slurm};
    if ((rc = slurm_write_job_script(script, &js, e)))
        return rc;
    memset(sl, 0, sizeof *sl);
    sl->st = SL_STARTED;
    sl->j = L->plan_index;
    sl->seq = x->seq++;
    snprintf(sl->run_dir, sizeof sl->run_dir, "%s", L->run_dir);
    return 0;
}

struct seq_slot {
    long long seq;
    int slot;
};

static int cmp_seq(const void *a, const void *b)
{
    long long d = ((const struct seq_slot *)a)->seq - ((const struct seq_slot *)b)->seq;
    return d < 0 ? -1 : d > 0;
}

/* Whether any task of an array is still followed. */
static int array_active(const struct slurm_backend *x, const char *array)
{
    size_t n = strlen(array);
    if (!n)
        return 0;
    for (int i = 0; i < x->nslots; i++)
        if (x->slots[i].st == SL_SUBMITTED && strncmp(x->slots[i].id, array, n) == 0 &&
            x->slots[i].id[n] == '_')
            return 1;
    return 0;
}

static void fail_slots(struct slurm_backend *x, const int *slots, int n, const char *why)
{
    for (int i = 0; i < n; i++) {
        struct sl_slot *sl = &x->slots[slots[i]];
        sl->st = SL_REPORT;
        sl->report = REP_SUBMIT_FAILED;
        snprintf(sl->msg, sizeof sl->msg, "%s", why);
    }
}

/* One array of n started slots of one group. */
static void submit_array(struct backend *b, const int *slots, int n)
{
    struct slurm_backend *x = b->impl;
    struct err e = {0};
    if (launch_mkdirs(x->slurm_dir, &e) != 0) {
        fail_slots(x, slots, n, e.msg);
        return;
    }
    char stamp[32], path[sizeof x->slurm_dir + 96], output[sizeof path];
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%S", &tm);
    snprintf(path, sizeof path, "%s/array-%s-%d-%d.sbatch", x->slurm_dir, stamp, (int)getpid(),
             x->narrays);
    snprintf(output, sizeof output, "%s/array-%s-%d-%d.out", x->slurm_dir, stamp, (int)getpid(),
             x->narrays);
    x->narrays++;
    char **scripts = calloc((size_t)n, sizeof *scripts);
    char (*ids)[32] = calloc((size_t)n, sizeof *ids);
    const char **idp = calloc((size_t)n, sizeof *idp);
    int bad = !scripts || !ids || !idp;
    for (int i = 0; i < n && !bad; i++) {
        size_t len = strlen(x->slots[slots[i]].run_dir) + 16;
        scripts[i] = malloc(len);
        bad = !scripts[i];
        if (!bad)
            snprintf(scripts[i], len, "%s/job.sbatch", x->slots[slots[i]].run_dir);
    }
    const struct slurm_job_res *jr = &x->groups[x->group_of[x->slots[slots[0]].j]];
    struct slurm_array_script as = {x->s->name, x->job_name, output, (const char *const *)scripts,
                                    n, x->s->max_running, jr, &x->s->slurm};
    int rc = bad ? err_nomem(&e, "array") : slurm_write_array_script(path, &as, &e);
    char *out = NULL, why[1024] = "";
    int status = 0;
    if (!rc) {
        char dep[64];
        const char *args[6];
        int na = 0;
        args[na++] = "--parsable";
        args[na++] = "--hold";
        /* the throttle holds for the study: an array starts after the one before */
        if (x->s->max_running > 0 && array_active(x, x->last_array)) {
            snprintf(dep, sizeof dep, "--dependency=afterany:%s", x->last_array);
            args[na++] = dep;
        }
        args[na++] = path;
        args[na] = NULL;
        rc = slurm_cli_run(&x->cli, SP_SBATCH, args, &out, why, sizeof why, &status, &e);
        if (!rc && status != 0)
            rc = err_set(&e, ERR_RUNTIME, "sbatch %s failed (exit %d): %s", path, status, why);
    }
    long array = 0;
    if (!rc) {
        char *end;
        array = strtol(out, &end, 10);
        if (array <= 0 || (*end && *end != ';' && *end != '\n'))
            rc = err_set(&e, ERR_RUNTIME, "sbatch --parsable answered '%.100s', not a job id",
                         out);
    }
    free(out);
    if (!rc) {
        for (int i = 0; i < n; i++) {
            snprintf(ids[i], sizeof ids[i], "%ld_%d", array, i);
            idp[i] = ids[i];
        }
        rc = b->submitted ? b->submitted(b->submitted_ctx, n, slots, idp, "PENDING", &e) : 0;
        char arr[32];
        snprintf(arr, sizeof arr, "%ld", array);
        if (rc) {
            /* not recorded: it must never run */
            const char *cargs[] = {arr, NULL};
            struct err ce = {0};
            char *o2;
            if (slurm_cli_run(&x->cli, SP_SCANCEL, cargs, &o2, why, sizeof why, &status, &ce) == 0)
                free(o2);
        } else {
            for (int i = 0; i < n; i++) {
                struct sl_slot *sl = &x->slots[slots[i]];
                sl->st = SL_SUBMITTED;
                snprintf(sl->id, sizeof sl->id, "%s", ids[i]);
            }
            x->nsubmitted += n;
            x->arrays_submitted++;
            snprintf(x->last_array, sizeof x->last_array, "%s", arr);
            /* a release that fails is tried again at the next poll (held tasks) */
            const char *rargs[] = {"release", arr, NULL};
            struct err re = {0};
            char *o2;
            if (slurm_cli_run(&x->cli, SP_SCONTROL, rargs, &o2, why, sizeof why, &status, &re) == 0)
                free(o2);
        }
    }
    if (rc)
        fail_slots(x, slots, n, e.msg);
    for (int i = 0; scripts && i < n; i++)
        free(scripts[i]);
    free(scripts);
    free(ids);
    free(idp);
}

static void submit_started(struct backend *b)
{
    struct slurm_backend *x = b->impl;
    int n = 0;
    for (int i = 0; i < x->nslots; i++)
        n += x->slots[i].st == SL_STARTED;
    if (!n)
        return;
    double t0 = sys_mono();
    struct seq_slot *ss = malloc((size_t)n * sizeof *ss);
    int *order = malloc((size_t)n * sizeof *order), *chunk = malloc((size_t)n * sizeof *chunk);
    if (!ss || !order || !chunk) {
        free(ss);
        free(order);
        free(chunk);
        return;   /* tried again at the next wait */
    }
    n = 0;
    for (int i = 0; i < x->nslots; i++)
        if (x->slots[i].st == SL_STARTED)
            ss[n++] = (struct seq_slot){x->slots[i].seq, i};
    qsort(ss, (size_t)n, sizeof *ss, cmp_seq);
    for (int k = 0; k < n; k++)
        order[k] = ss[k].slot;
    free(ss);
    /* one array per group of equal resources, in start order, split at MaxArraySize */
    for (int g = 0; g < x->ngroups; g++) {
        int m = 0;
        for (int k = 0; k < n; k++) {
            if (x->group_of[x->slots[order[k]].j] != g)
                continue;
            chunk[m++] = order[k];
            if (m == x->max_array) {
                submit_array(b, chunk, m);
                m = 0;
            }
        }
        if (m)
            submit_array(b, chunk, m);
    }
    free(order);
    free(chunk);
    x->submit_s += sys_mono() - t0;
}

/* --- cancelling ---------------------------------------------------------------- */

static void sl_cancel(struct backend *b, int slot)
{
    struct slurm_backend *x = b->impl;
    struct sl_slot *sl = &x->slots[slot];
    if (sl->st == SL_STARTED) {
        sl->st = SL_REPORT;
        sl->report = REP_CANCELLED;
        snprintf(sl->msg, sizeof sl->msg,
                 "cancelled: the runner was asked to stop (before it was submitted)");
    } else if (sl->st == SL_SUBMITTED) {
        sl->cancel_req = 1;
    }
}

static void sl_release(struct backend *b, int slot)
{
    struct slurm_backend *x = b->impl;
    struct sl_slot *sl = &x->slots[slot];
    if (sl->st == SL_STARTED || sl->st == SL_SUBMITTED) {
        sl->st = SL_REPORT;
        sl->report = REP_FORGOTTEN;
        snprintf(sl->msg, sizeof sl->msg, "another runner follows this attempt now");
    }
}

static void send_cancels(struct slurm_backend *x)
{
    int n = 0;
    for (int i = 0; i < x->nslots; i++)
        n += x->slots[i].st == SL_SUBMITTED && x->slots[i].cancel_req && !x->slots[i].cancel_sent;
    if (!n)
        return;
    const char **args = calloc((size_t)n + 1, sizeof *args);
    if (!args)
        return;
    n = 0;
    for (int i = 0; i < x->nslots; i++) {
        struct sl_slot *sl = &x->slots[i];
        if (sl->st == SL_SUBMITTED && sl->cancel_req && !sl->cancel_sent) {
            args[n++] = sl->id;
            sl->cancel_sent = 1;
        }
    }
    char *out, why[512];
    int status;
    struct err e = {0};
    if (slurm_cli_run(&x->cli, SP_SCANCEL, args, &out, why, sizeof why, &status, &e) == 0)
        free(out);
    free(args);
    x->next_poll = 0;   /* see them end soon */
}

/* --- polling ------------------------------------------------------------------- */

struct id_index {
    const char *id;
    int slot;
};

static int cmp_index(const void *a, const void *b)
{
    return strcmp(((const struct id_index *)a)->id, ((const struct id_index *)b)->id);
}

static int report(struct slurm_backend *x, int slot, struct outcome *o, backend_done_fn done,
                  void *ctx)
{
    x->slots[slot].st = SL_FREE;
    done(ctx, slot, o);
    return 1;
}

static int has_result(const char *dir)
{
    char path[4096 + 32];
    snprintf(path, sizeof path, "%s/result.json", dir);
    struct stat sb;
    return stat(path, &sb) == 0;
}

static void cancelled_outcome(struct outcome *o, const char *msg)
{
    memset(o, 0, sizeof *o);
    o->status = RS_CANCELLED;
    o->failure = FC_NONE;
    o->exit_code = -1;
    o->last_step = -1;
    o->resumed_from_step = -1;
    o->started = o->finished = sys_now();
    sys_hostname(o->host, sizeof o->host);
    snprintf(o->slurm_state, sizeof o->slurm_state, "CANCELLED");
    snprintf(o->message, sizeof o->message, "%s", msg);
}

/* A task Slurm held after its batch launch failed, which the runner then
 * cancelled: not the job's fault, so it runs again (with the runner's
 * back-off for infrastructure failures, which stops a campaign whose
 * nodes keep failing). */
static void launch_failed_outcome(struct outcome *o, const struct sl_slot *sl)
{
    outcome_free(o);
    outcome_start_failure(o, "");
    snprintf(o->slurm_state, sizeof o->slurm_state, "CANCELLED");
    snprintf(o->message, sizeof o->message,
             "Slurm could not start it on %s and held it (launch failed requeued held); "
             "cancelled: not the job's fault, it runs again",
             sl->launch_node);
}

/* A task gone from the controller's memory before we saw it end: a pending
 * array task cancelled by its id leaves no record at all; otherwise the
 * runner was away longer than MinJobAge.  Its files say what they can. */
static void vanished_outcome(struct outcome *o, const struct sl_slot *sl)
{
    char path[4096 + 16];
    struct stat sb;
    snprintf(path, sizeof path, "%s/stdout", sl->run_dir);
    if (sl->cancel_req) {
        cancelled_outcome(o, "cancelled: the runner was asked to stop");
        return;
    }
    if (stat(path, &sb) != 0) {   /* the job script never ran */
        cancelled_outcome(o, "cancelled in Slurm before it started (scancel)");
        return;
    }
    struct slurm_task t;
    memset(&t, 0, sizeof t);
    snprintf(t.id, sizeof t.id, "%s", sl->id);
    snprintf(t.state, sizeof t.state, "COMPLETED");
    slurm_outcome(o, &t, sl->run_dir, 0, NULL);
    if (o->status != RS_DONE) {
        char was[OUTCOME_MSG_MAX];
        snprintf(was, sizeof was, "%s", o->message);
        outcome_free(o);
        outcome_start_failure(o, "");
        o->slurm_state[0] = '\0';
        snprintf(o->message, sizeof o->message,
                 "Slurm job %s left the controller's memory before the runner saw how it ended "
                 "(%s); not charged to the job, it runs again",
                 sl->id, was);
    } else {
        o->slurm_state[0] = '\0';
    }
}

struct ended {
    int slot;
    int known;                /* t holds what Slurm said */
    struct slurm_task t;
    double rss_mib;
};

/* Accounting, when the cluster has it: MaxRSS of the tasks that ended, and
 * how the tasks that left the controller's memory ended -- one sacct call. */
static void ask_accounting(struct slurm_backend *x, struct ended *en, int n)
{
    size_t len = 1;
    for (int i = 0; i < n; i++)
        len += strlen(x->slots[en[i].slot].id) + 1;
    char *ids = malloc(len + 8), fmt[128];
    if (!ids)
        return;
    ids[0] = '\0';
    for (int i = 0; i < n; i++) {
        strcat(ids, i ? "," : "");
        strcat(ids, x->slots[en[i].slot].id);
    }
    char *jobs = malloc(len + 16);
    if (!jobs) {
        free(ids);
        return;
    }
    snprintf(jobs, len + 16, "--jobs=%s", ids);
    snprintf(fmt, sizeof fmt, "--format=%s", slurm_sacct_format);
    const char *args[] = {"--noheader", "--parsable2", jobs, fmt, NULL};
    char *text = NULL, why[512];
    int status;
    struct err e = {0};
    if (slurm_cli_run(&x->cli, SP_SACCT, args, &text, why, sizeof why, &status, &e) == 0 &&
        status == 0) {
        for (char *l = text; l && *l;) {
            char *nl = strchr(l, '\n');
            if (nl)
                *nl = '\0';
            struct slurm_task t;
            int step;
            double rss;
            if (slurm_parse_sacct(l, &t, &step, &rss) == 0)
                for (int i = 0; i < n; i++) {
                    if (strcmp(t.id, x->slots[en[i].slot].id) != 0)
                        continue;
                    if (rss > en[i].rss_mib)
                        en[i].rss_mib = rss;
                    if (!step && !en[i].known && slurm_state_final(t.state)) {
                        en[i].t = t;
                        en[i].known = 1;
                    }
                }
            l = nl ? nl + 1 : NULL;
        }
    }
    free(text);
    free(jobs);
    free(ids);
}

static int poll_queue(struct backend *b, backend_done_fn done, void *ctx)
{
    struct slurm_backend *x = b->impl;
    int n = 0;
    for (int i = 0; i < x->nslots; i++)
        n += x->slots[i].st == SL_SUBMITTED;
    if (!n)
        return 0;
    struct id_index *ix = malloc((size_t)n * sizeof *ix);
    char *seen = calloc((size_t)x->nslots, 1);
    int *started = malloc((size_t)n * sizeof *started), nstarted = 0, nended = 0;
    const char **started_ids = malloc((size_t)n * sizeof *started_ids);
    struct ended *en = malloc((size_t)n * sizeof *en);
    if (!ix || !seen || !started || !started_ids || !en) {
        free(ix);
        free(seen);
        free(started);
        free(started_ids);
        free(en);
        return 0;
    }
    n = 0;
    for (int i = 0; i < x->nslots; i++)
        if (x->slots[i].st == SL_SUBMITTED)
            ix[n++] = (struct id_index){x->slots[i].id, i};
    qsort(ix, (size_t)n, sizeof *ix, cmp_index);
    char name_opt[sizeof x->job_name + 16];
    snprintf(name_opt, sizeof name_opt, "--name=%s", x->job_name);
    const char *args[] = {"--noheader", "--array", "--states=all", name_opt, "--Format",
                          slurm_squeue_format, NULL};
    char *text = NULL, why[512];
    int status, reported = 0;
    struct err e = {0};
    x->polls++;
    if (slurm_cli_run(&x->cli, SP_SQUEUE, args, &text, why, sizeof why, &status, &e) != 0 ||
        status != 0) {
        /* the controller may be busy or restarting: look again next time */
        if (++x->squeue_failures % 10 == 1)
            fprintf(stderr, "cascade: squeue failed (%s); trying again\n",
                    e.msg[0] ? e.msg : why);
        free(text);
        free(ix);
        free(seen);
        free(started);
        free(started_ids);
        free(en);
        return 0;
    }
    x->squeue_failures = 0;
    char held[4096] = "";
    for (char *l = text; l && *l;) {
        char *nl = strchr(l, '\n');
        if (nl)
            *nl = '\0';
        struct slurm_task t;
        struct id_index key = {t.id, 0}, *hit = NULL;
        if (slurm_parse_task(l, &t) == 0)
            hit = bsearch(&key, ix, (size_t)n, sizeof *ix, cmp_index);
        l = nl ? nl + 1 : NULL;
        if (!hit)
            continue;
        struct sl_slot *sl = &x->slots[hit->slot];
        if (sl->st != SL_SUBMITTED || seen[hit->slot])
            continue;
        seen[hit->slot] = 1;
        sl->missing = 0;
        if (strcmp(t.state, "RUNNING") == 0 && !sl->seen_running) {
            sl->seen_running = 1;
            started_ids[nstarted] = sl->id;
            started[nstarted++] = hit->slot;
        }
        if (!slurm_state_final(t.state)) {
            switch (slurm_queued_action(&t, sl->cancel_sent)) {
            case SQ_CANCEL_AGAIN:
                sl->cancel_sent = 0;   /* send_cancels sends it again */
                break;
            case SQ_LAUNCH_FAILED:
                if (!sl->cancel_req) {
                    sl->cancel_req = 1;
                    sl->launch_failed = 1;
                    snprintf(sl->launch_node, sizeof sl->launch_node, "%s",
                             t.nodes[0] ? t.nodes : "its node");
                }
                break;
            case SQ_WAIT:
                break;
            }
            /* submitted held by a runner that died before releasing it */
            if (strcmp(t.reason, "JobHeldUser") == 0 && strlen(held) + 40 < sizeof held) {
                char arr[32];
                snprintf(arr, sizeof arr, "%.*s", (int)strcspn(t.id, "_"), t.id);
                if (!strstr(held, arr))
                    snprintf(held + strlen(held), sizeof held - strlen(held), "%s%s",
                             held[0] ? "," : "", arr);
            }
            continue;
        }
        /* a shared file system may show result.json a little later */
        if (strcmp(t.state, "COMPLETED") == 0 && !has_result(sl->run_dir) && sl->no_result < 3) {
            sl->no_result++;
            continue;
        }
        en[nended++] = (struct ended){hit->slot, 1, t, 0};
    }
    free(text);
    for (int k = 0; k < n; k++) {
        int i = ix[k].slot;
        struct sl_slot *sl = &x->slots[i];
        /* twice absent: gone from the controller (MinJobAge) */
        if (!seen[i] && sl->st == SL_SUBMITTED && ++sl->missing >= 2) {
            memset(&en[nended], 0, sizeof en[nended]);
            en[nended++].slot = i;
        }
    }
    if (x->accounting && nended)
        ask_accounting(x, en, nended);
    /* cascade status tells queued from running by what the runner saw last */
    if (nstarted && b->submitted &&
        b->submitted(b->submitted_ctx, nstarted, started, started_ids, "RUNNING", &e) != 0)
        fprintf(stderr, "cascade: cannot record that Slurm jobs started: %s\n", e.msg);
    for (int k = 0; k < nended; k++) {
        struct sl_slot *sl = &x->slots[en[k].slot];
        struct outcome o;
        if (en[k].known) {
            char limit[SLURM_VALUE_MAX];
            snprintf(limit, sizeof limit, "%s", x->groups[x->group_of[sl->j]].v[SR_TIME]);
            slurm_outcome(&o, &en[k].t, sl->run_dir, sl->cancel_req, limit);
        } else {
            vanished_outcome(&o, sl);
        }
        if (en[k].rss_mib > 0)
            o.peak_rss_mib = en[k].rss_mib;
        if (sl->launch_failed)
            launch_failed_outcome(&o, sl);
        reported += report(x, en[k].slot, &o, done, ctx);
    }
    free(started);
    free(started_ids);
    free(en);
    free(ix);
    free(seen);
    if (held[0]) {
        const char *rargs[] = {"release", held, NULL};
        char *o2;
        if (slurm_cli_run(&x->cli, SP_SCONTROL, rargs, &o2, why, sizeof why, &status, &e) == 0)
            free(o2);
    }
    return reported;
}

static int report_local(struct slurm_backend *x, backend_done_fn done, void *ctx)
{
    int reported = 0;
    for (int i = 0; i < x->nslots; i++) {
        struct sl_slot *sl = &x->slots[i];
        if (sl->st != SL_REPORT)
            continue;
        struct outcome o;
        if (sl->report == REP_SUBMIT_FAILED) {
            outcome_start_failure(&o, sl->msg);
        } else {
            cancelled_outcome(&o, sl->msg);
            o.slurm_state[0] = '\0';
        }
        reported += report(x, i, &o, done, ctx);
    }
    return reported;
}

static int sl_wait(struct backend *b, double max_wait, backend_done_fn done, void *ctx)
{
    struct slurm_backend *x = b->impl;
    submit_started(b);
    send_cancels(x);
    int reported = report_local(x, done, ctx);
    double now = sys_mono();
    int submitted = 0;
    for (int i = 0; i < x->nslots && !submitted; i++)
        submitted = x->slots[i].st == SL_SUBMITTED;
    if (submitted && now >= x->next_poll) {
        long before = 0, after = 0;
        for (int k = 0; k < SP_COUNT; k++)
            before += x->cli.calls[k];
        reported += poll_queue(b, done, ctx);
        for (int k = 0; k < SP_COUNT; k++)
            after += x->cli.calls[k];
        x->poll_calls += after - before;
        x->next_poll = sys_mono() + x->s->slurm.poll_s;
    }
    double t = reported ? 0 : max_wait;
    if (submitted && x->next_poll - now < t)
        t = x->next_poll - now;
    if (t < 0)
        t = 0;
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    sigaddset(&set, SIGCHLD);
    struct timespec ts = {(time_t)t, (long)((t - (double)(time_t)t) * 1e9)};
    int sig = sigtimedwait(&set, NULL, &ts);
    /* SIGCHLD: a client program we already waited for */
    struct timespec zero = {0, 0};
    sigset_t chld;
    sigemptyset(&chld);
    sigaddset(&chld, SIGCHLD);
    while (sigtimedwait(&chld, NULL, &zero) > 0) {
    }
    return sig == SIGINT || sig == SIGTERM || sig == SIGHUP ? sig : 0;
}

static int sl_adopt(struct backend *b, int slot, long plan_index, const char *run_dir,
                    const char *external_id, struct err *e)
{
    struct slurm_backend *x = b->impl;
    struct sl_slot *sl = &x->slots[slot];
    if (slot < 0 || slot >= x->nslots || sl->st != SL_FREE)
        return err_set(e, ERR_RUNTIME, "no free slot for Slurm job %s", external_id);
    memset(sl, 0, sizeof *sl);
    sl->st = SL_SUBMITTED;
    sl->j = plan_index;
    sl->seq = x->seq++;
    snprintf(sl->run_dir, sizeof sl->run_dir, "%s", run_dir);
    snprintf(sl->id, sizeof sl->id, "%s", external_id);
    /* new arrays queue behind the newest adopted one */
    long a = atol(external_id);
    if (x->s->max_running > 0 && a > atol(x->last_array))
        snprintf(x->last_array, sizeof x->last_array, "%ld", a);
    x->next_poll = 0;
    return 0;
}

static void sl_destroy(struct backend *b)
{
    struct slurm_backend *x = b->impl;
    if (!x)
        return;
    /* jobs in Slurm go on: the next runner adopts them */
    slurm_cli_fini(&x->cli);
    free(x->groups);
    free(x->group_of);
    free(x->slots);
    free(x);
    b->impl = NULL;
}

int backend_slurm_create(struct backend *b, const struct study *s, const struct plan *p,
                         const char *runs, struct err *e)
{
    memset(b, 0, sizeof *b);
    struct slurm_backend *x = calloc(1, sizeof *x);
    if (!x)
        return err_nomem(e, "slurm backend");
    b->impl = x;
    b->destroy = sl_destroy;
    x->s = s;
    x->p = p;
    int rc = slurm_cli_init(&x->cli, e);
    if (rc) {
        sl_destroy(b);
        return rc;
    }
    snprintf(x->job_name, sizeof x->job_name, "cascade.%s", s->name);
    if (runs[0] == '/') {
        snprintf(x->runs_root, sizeof x->runs_root, "%s", runs);
    } else {
        char cwd[2048];
        if (!getcwd(cwd, sizeof cwd))
            snprintf(cwd, sizeof cwd, ".");
        snprintf(x->runs_root, sizeof x->runs_root, "%s/%s", cwd, runs);
    }
    snprintf(x->slurm_dir, sizeof x->slurm_dir, "%s/%s/slurm", x->runs_root, s->name);
    if (!slurm_path_ok(x->slurm_dir)) {
        rc = err_set(e, ERR_INPUT, "the runs directory %s holds characters an #SBATCH line "
                                   "cannot carry (blanks, quotes, %%, #, $, ...): choose another "
                                   "--runs directory",
                     x->runs_root);
        sl_destroy(b);
        return rc;
    }
    /* the resources of every job, grouped */
    x->group_of = calloc((size_t)(p->njobs ? p->njobs : 1), sizeof *x->group_of);
    if (!x->group_of) {
        sl_destroy(b);
        return err_nomem(e, "slurm groups");
    }
    int cap = 0;
    for (long j = 0; j < p->njobs && !rc; j++) {
        struct slurm_job_res jr;
        slurm_spec_job(s, p->jobs[j].prep >= 0 ? -1 : p->jobs[j].sweep, &jr);
        int g = 0;
        while (g < x->ngroups && memcmp(x->groups[g].v, jr.v, sizeof jr.v) != 0)
            g++;
        if (g == x->ngroups) {
            if (x->ngroups == cap) {
                cap = cap ? 2 * cap : 8;
                struct slurm_job_res *gr = realloc(x->groups, (size_t)cap * sizeof *gr);
                if (!gr) {
                    rc = err_nomem(e, "slurm groups");
                    break;
                }
                x->groups = gr;
            }
            x->groups[x->ngroups++] = jr;
        }
        x->group_of[j] = g;
    }
    long max_submit = 0;
    if (!rc)
        rc = read_limits(x, &max_submit, e);
    struct partition *pt = NULL;
    int npt = 0;
    if (!rc)
        rc = read_partitions(x, &pt, &npt, e);
    for (int g = 0; g < x->ngroups && !rc; g++)
        rc = check_group(x, g, pt, npt, e);
    free(pt);
    if (rc) {
        sl_destroy(b);
        return rc;
    }
    if (s->slurm.max_submit > 0 && s->slurm.max_submit < max_submit)
        max_submit = s->slurm.max_submit;
    long n = p->njobs < max_submit ? p->njobs : max_submit;
    x->nslots = n < 1 ? 1 : (int)n;
    x->slots = calloc((size_t)x->nslots, sizeof *x->slots);
    if (!x->slots) {
        sl_destroy(b);
        return err_nomem(e, "slurm slots");
    }
    b->nslots = x->nslots;
    b->start = sl_start;
    b->wait = sl_wait;
    b->cancel = sl_cancel;
    b->adopt = sl_adopt;
    b->release = sl_release;
    return 0;
}
