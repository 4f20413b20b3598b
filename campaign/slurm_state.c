/* slurm_state: squeue lines and Slurm states as outcomes. */
#define _XOPEN_SOURCE 700   /* strptime */
#include "slurm_state.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#include "sysinfo.h"

const char slurm_squeue_format[] =
    "JobArrayID:|,State:|,exit_code:|,TimeUsed:|,StartTime:|,EndTime:|,Reason:|,NodeList:";

double slurm_elapsed_seconds(const char *t)
{
    /* [D-]H:MM:SS or M:SS */
    long d = 0, f[3];
    int n = 0;
    const char *p = t, *dash = strchr(t, '-');
    if (dash) {
        d = strtol(t, NULL, 10);
        p = dash + 1;
    }
    while (*p && n < 3) {
        char *end;
        f[n++] = strtol(p, &end, 10);
        if (end == p)
            return -1;
        p = *end == ':' ? end + 1 : end;
        if (*end != ':')
            break;
    }
    if (*p || n < 2)
        return -1;
    double s = n == 2 ? (double)(f[0] * 60 + f[1]) : (double)(f[0] * 3600 + f[1] * 60 + f[2]);
    return s + 86400.0 * (double)d;
}

static double parse_time(const char *t)
{
    struct tm tm;
    memset(&tm, 0, sizeof tm);
    const char *end = strptime(t, "%Y-%m-%dT%H:%M:%S", &tm);
    if (!end || *end)
        return 0;
    tm.tm_isdst = -1;   /* squeue prints local time */
    time_t u = mktime(&tm);
    return u == (time_t)-1 ? 0 : (double)u;
}

static void field(char *out, size_t len, const char *from, size_t n)
{
    if (n >= len)
        n = len - 1;
    memcpy(out, from, n);
    out[n] = '\0';
    while (n > 0 && out[n - 1] == ' ')
        out[--n] = '\0';
}

int slurm_parse_task(const char *line, struct slurm_task *t)
{
    memset(t, 0, sizeof *t);
    const char *f[8];
    size_t fl[8];
    const char *p = line;
    for (int k = 0; k < 8; k++) {
        const char *bar = k < 7 ? strchr(p, '|') : NULL;
        if (k < 7 && !bar)
            return -1;
        f[k] = p;
        fl[k] = bar ? (size_t)(bar - p) : strcspn(p, "\r\n");
        p = bar ? bar + 1 : p;
    }
    char tmp[64];
    field(t->id, sizeof t->id, f[0], fl[0]);
    field(t->state, sizeof t->state, f[1], fl[1]);
    field(tmp, sizeof tmp, f[2], fl[2]);
    t->exit_status = atoi(tmp);
    field(tmp, sizeof tmp, f[3], fl[3]);
    t->elapsed_s = slurm_elapsed_seconds(tmp);
    if (t->elapsed_s < 0)
        t->elapsed_s = 0;
    field(tmp, sizeof tmp, f[4], fl[4]);
    t->start = parse_time(tmp);
    field(tmp, sizeof tmp, f[5], fl[5]);
    t->end = parse_time(tmp);
    field(t->reason, sizeof t->reason, f[6], fl[6]);
    field(t->nodes, sizeof t->nodes, f[7], fl[7]);
    /* "CANCELLED by 0" in some versions */
    char *sp = strchr(t->state, ' ');
    if (sp)
        *sp = '\0';
    return t->id[0] && t->state[0] ? 0 : -1;
}

static const char *const final_states[] = {"COMPLETED", "FAILED",    "OUT_OF_MEMORY", "TIMEOUT",
                                           "DEADLINE",  "NODE_FAIL", "PREEMPTED",     "BOOT_FAIL",
                                           "REVOKED",   "CANCELLED", NULL};

int slurm_state_final(const char *state)
{
    for (int i = 0; final_states[i]; i++)
        if (strcmp(state, final_states[i]) == 0)
            return 1;
    return 0;
}

/* squeue prints reasons with spaces, scontrol with underscores */
static int reason_is(const char *reason, const char *words)
{
    for (; *reason && *words; reason++, words++)
        if (*reason != *words && !(*reason == '_' && *words == ' '))
            return 0;
    return *reason == '\0' && *words == '\0';
}

enum slurm_queued_action slurm_queued_action(const struct slurm_task *t, int cancel_sent)
{
    int pending = strcmp(t->state, "PENDING") == 0 || strcmp(t->state, "REQUEUED") == 0 ||
                  strcmp(t->state, "REQUEUE_HOLD") == 0;
    /* A task whose batch launch fails while our scancel is on its way comes
     * back pending (requeued and held): the first cancel found nothing to
     * kill, so the runner would wait for it for ever.  A running task is
     * left alone: it is ending, and a second scancel adds nothing. */
    if (cancel_sent)
        return pending ? SQ_CANCEL_AGAIN : SQ_WAIT;
    /* Slurm holds a task whose batch script could not be started on its
     * node (slurmd did not confirm the launch) until an administrator
     * releases it; a campaign cannot wait for that. */
    if (pending && reason_is(t->reason, "launch failed requeued held"))
        return SQ_LAUNCH_FAILED;
    return SQ_WAIT;
}

void slurm_outcome(struct outcome *o, const struct slurm_task *t, const char *run_dir,
                   int by_runner, const char *limit)
{
    memset(o, 0, sizeof *o);
    const char *st = t->state;
    int timeout = strcmp(st, "TIMEOUT") == 0 || strcmp(st, "DEADLINE") == 0;
    int cancelled = strcmp(st, "CANCELLED") == 0;
    int infra = strcmp(st, "NODE_FAIL") == 0 || strcmp(st, "PREEMPTED") == 0 ||
                strcmp(st, "BOOT_FAIL") == 0 || strcmp(st, "REVOKED") == 0;
    struct exit_info x = {t->exit_status, timeout, cancelled && by_runner, 0, 0};
    outcome_collect(o, run_dir, &x);
    snprintf(o->slurm_state, sizeof o->slurm_state, "%s", st);
    if (timeout) {
        snprintf(o->message, sizeof o->message, "timeout: Slurm ended it at its time limit%s%s (%s)",
                 limit && limit[0] ? " of " : "", limit ? limit : "", st);
    } else if (cancelled && !by_runner) {
        o->status = RS_CANCELLED;
        o->failure = FC_NONE;
        snprintf(o->message, sizeof o->message,
                 "cancelled in Slurm (scancel or cascade cancel)");
    } else if (infra) {
        o->status = RS_CANCELLED;
        o->failure = FC_INFRA;
        snprintf(o->message, sizeof o->message,
                 "Slurm %s on %s: not the job's fault, it runs again", st,
                 t->nodes[0] ? t->nodes : "its node");
    } else if (strcmp(st, "OUT_OF_MEMORY") == 0) {
        o->status = RS_FAILED;
        o->failure = FC_JOB;
        char was[OUTCOME_MSG_MAX];
        snprintf(was, sizeof was, "%s", o->message);
        snprintf(o->message, sizeof o->message,
                 "out of memory: Slurm ended it for using more than its --mem (%s)", was);
    } else if (strcmp(st, "COMPLETED") != 0 && strcmp(st, "FAILED") != 0 && !cancelled) {
        o->status = RS_FAILED;
        o->failure = FC_JOB;
        snprintf(o->message, sizeof o->message, "Slurm state %s", st);
    }
    if (t->nodes[0])
        snprintf(o->host, sizeof o->host, "%s", t->nodes);
    o->wall_s = t->elapsed_s;
    o->started = t->start > 0 ? t->start : sys_now() - t->elapsed_s;
    o->finished = t->end > 0 ? t->end : sys_now();
}

const char slurm_sacct_format[] = "JobID,State,ExitCode,Elapsed,NodeList,Start,End,MaxRSS";

static double rss_mib(const char *t)
{
    char *end;
    double v = strtod(t, &end);
    if (end == t || v < 0)
        return 0;
    switch (*end) {
    case 'K': return v / 1024.0;
    case 'M': return v;
    case 'G': return v * 1024.0;
    case 'T': return v * 1024.0 * 1024.0;
    default: return v / (1024.0 * 1024.0);   /* bytes */
    }
}

int slurm_parse_sacct(const char *line, struct slurm_task *t, int *step, double *rss)
{
    memset(t, 0, sizeof *t);
    const char *f[8];
    size_t fl[8];
    const char *p = line;
    for (int k = 0; k < 8; k++) {
        const char *bar = k < 7 ? strchr(p, '|') : NULL;
        if (k < 7 && !bar)
            return -1;
        f[k] = p;
        fl[k] = bar ? (size_t)(bar - p) : strcspn(p, "|\r\n");
        p = bar ? bar + 1 : p;
    }
    char tmp[64];
    field(t->id, sizeof t->id, f[0], fl[0]);
    char *dot = strchr(t->id, '.');
    *step = dot != NULL;
    if (dot)
        *dot = '\0';
    field(t->state, sizeof t->state, f[1], fl[1]);
    char *sp = strchr(t->state, ' ');
    if (sp)
        *sp = '\0';
    /* ExitCode "code:signal" */
    field(tmp, sizeof tmp, f[2], fl[2]);
    int code = atoi(tmp), sig = strchr(tmp, ':') ? atoi(strchr(tmp, ':') + 1) : 0;
    t->exit_status = sig ? (sig & 0x7f) : (code & 0xff) << 8;
    field(tmp, sizeof tmp, f[3], fl[3]);
    t->elapsed_s = slurm_elapsed_seconds(tmp);
    if (t->elapsed_s < 0)
        t->elapsed_s = 0;
    field(t->nodes, sizeof t->nodes, f[4], fl[4]);
    if (strcmp(t->nodes, "None assigned") == 0)
        t->nodes[0] = '\0';
    field(tmp, sizeof tmp, f[5], fl[5]);
    t->start = parse_time(tmp);
    field(tmp, sizeof tmp, f[6], fl[6]);
    t->end = parse_time(tmp);
    field(tmp, sizeof tmp, f[7], fl[7]);
    *rss = rss_mib(tmp);
    return t->id[0] && t->state[0] ? 0 : -1;
}
