/* outcome: classifying a finished job and reading what it left. */
#include "outcome.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/wait.h>

#include "sysinfo.h"
#include "util/mem.h"
#include "util/sha256.h"

static const char *const status_names[] = {"running", "done",     "failed",   "crashed",
                                           "timeout", "diverged", "cancelled"};

const char *run_status_name(enum run_status s)
{
    return status_names[s];
}

int run_status_retryable(enum run_status s)
{
    return s == RS_FAILED || s == RS_CRASHED || s == RS_TIMEOUT;
}

const char *failure_class_name(enum failure_class c)
{
    static const char *const names[] = {NULL, "job", "infrastructure", "deterministic"};
    return names[c];
}

const char *outcome_signal_name(int sig, char *buf, size_t len)
{
    /* by macro, not number: the numbers differ between architectures */
    static const struct {
        int sig;
        const char *name;
    } names[] = {
        {SIGHUP, "SIGHUP"},   {SIGINT, "SIGINT"},       {SIGQUIT, "SIGQUIT"}, {SIGILL, "SIGILL"},
        {SIGTRAP, "SIGTRAP"}, {SIGABRT, "SIGABRT"},     {SIGBUS, "SIGBUS"},   {SIGFPE, "SIGFPE"},
        {SIGKILL, "SIGKILL"}, {SIGUSR1, "SIGUSR1"},     {SIGSEGV, "SIGSEGV"}, {SIGUSR2, "SIGUSR2"},
        {SIGPIPE, "SIGPIPE"}, {SIGALRM, "SIGALRM"},     {SIGTERM, "SIGTERM"}, {SIGCHLD, "SIGCHLD"},
        {SIGCONT, "SIGCONT"}, {SIGSTOP, "SIGSTOP"},     {SIGTSTP, "SIGTSTP"}, {SIGTTIN, "SIGTTIN"},
        {SIGTTOU, "SIGTTOU"}, {SIGURG, "SIGURG"},       {SIGXCPU, "SIGXCPU"}, {SIGXFSZ, "SIGXFSZ"},
        {SIGVTALRM, "SIGVTALRM"}, {SIGPROF, "SIGPROF"}, {SIGWINCH, "SIGWINCH"}, {SIGSYS, "SIGSYS"},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (names[i].sig == sig)
            return names[i].name;
    if (sig >= SIGRTMIN && sig <= SIGRTMAX)
        snprintf(buf, len, "SIGRTMIN+%d", sig - SIGRTMIN);
    else
        snprintf(buf, len, "signal %d", sig);
    return buf;
}

void outcome_start_failure(struct outcome *o, const char *why)
{
    memset(o, 0, sizeof *o);
    o->status = RS_CANCELLED;
    o->failure = FC_INFRA;
    o->exit_code = -1;
    o->last_step = -1;
    o->resumed_from_step = -1;
    o->started = o->finished = sys_now();
    sys_hostname(o->host, sizeof o->host);
    snprintf(o->message, sizeof o->message, "could not start: %s", why);
}

void outcome_file_tail(const char *path, int maxlines, char *out, size_t len)
{
    out[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f)
        return;
    char buf[16384];
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    long from = size > (long)sizeof buf - 1 ? size - (long)sizeof buf + 1 : 0;
    fseek(f, from, SEEK_SET);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == '\r'))
        buf[--n] = '\0';
    /* back up maxlines newlines */
    size_t start = n;
    int lines = 0;
    while (start > 0) {
        if (buf[start - 1] == '\n' && ++lines == maxlines)
            break;
        start--;
    }
    const char *tail = buf + start;
    size_t tl = strlen(tail);
    if (tl >= len)
        tail += tl - (len - 1);
    snprintf(out, len, "%s", tail);
}

static const char *last_line(const char *text)
{
    const char *nl = strrchr(text, '\n');
    return nl ? nl + 1 : text;
}

static const char *kind_of(const char *name)
{
    size_t n = strlen(name);
#define ENDS(s) (n >= strlen(s) && strcmp(name + n - strlen(s), s) == 0)
    if (strcmp(name, "case.yaml") == 0)
        return "case";
    if (strcmp(name, "result.json") == 0)
        return "result";
    if (strcmp(name, "stdout") == 0)
        return "stdout";
    if (strcmp(name, "stderr") == 0)
        return "stderr";
    if (strcmp(name, "thermo.csv") == 0)
        return "thermo";
    if (ENDS(".h5"))
        return "hdf5";
    if (ENDS(".xdmf"))
        return "xdmf";
    if (ENDS(".xyz"))
        return "xyz";
#undef ENDS
    return "other";
}

static int cmp_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The files the attempt left, with their sizes and checksums; -1 when out
 * of memory (the list would be incomplete: the caller must not record the
 * attempt as done with it). */
static int collect_artifacts(struct outcome *o, const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    char **names = NULL;
    int n = 0, cap = 0, oom = 0;
    struct dirent *de;
    while (!oom && (de = readdir(d))) {
        if (de->d_name[0] == '.')
            continue;
        char path[4096 + 256];
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        struct stat sb;
        if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
            continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 16;
            char **g = mem_realloc(names, (size_t)cap * sizeof *g);
            if (!g) {
                oom = 1;
                break;
            }
            names = g;
        }
        names[n] = mem_strdup(de->d_name);
        if (names[n])
            n++;
        else
            oom = 1;
    }
    closedir(d);
    if (n > 1)   /* names is NULL for an empty directory */
        qsort(names, (size_t)n, sizeof *names, cmp_name);
    o->artifacts = oom ? NULL : mem_calloc((size_t)(n ? n : 1), sizeof *o->artifacts);
    oom |= !o->artifacts;
    for (int i = 0; i < n; i++) {
        if (!oom) {
            struct artifact *a = &o->artifacts[o->nartifacts];
            snprintf(a->path, sizeof a->path, "%s/%s", dir, names[i]);
            snprintf(a->kind, sizeof a->kind, "%s", kind_of(names[i]));
            uint64_t bytes = 0;
            if (sha256_file_hex(a->path, a->sha256, &bytes) == 0) {
                a->bytes = (long long)bytes;
                o->nartifacts++;
            }
        }
        free(names[i]);
    }
    free(names);
    return oom ? -1 : 0;
}

static json_t *read_result(const char *dir)
{
    char path[4096 + 32];
    snprintf(path, sizeof path, "%s/result.json", dir);
    json_error_t je;
    json_t *r = json_load_file(path, 0, &je);
    if (r && !json_is_object(r)) {
        json_decref(r);
        r = NULL;
    }
    return r;
}

/* The value of the "step" column in the last complete row of the run's
 * thermo.csv or thermo.csv.tmp (the solver flushes every row), or -1: how far a run that did
 * not finish got, which tells a crash that repeats at the same step
 * (deterministic) from one that does not. */
static long thermo_last_step(const char *dir)
{
    char path[4096 + 32], line[8192];
    snprintf(path, sizeof path, "%s/thermo.csv", dir);
    FILE *f = fopen(path, "rb");
    if (!f) {
        /* cascade-solver writes thermo.csv.tmp until the run ends: a run
         * that crashed leaves that */
        snprintf(path, sizeof path, "%s/thermo.csv.tmp", dir);
        f = fopen(path, "rb");
    }
    if (!f)
        return -1;
    int col = -1;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        int k = 0;
        char *save = NULL;
        for (char *t = strtok_r(line, ",\r\n", &save); t; t = strtok_r(NULL, ",\r\n", &save), k++) {
            while (*t == ' ')
                t++;
            if (strncmp(t, "step", 4) == 0 && (t[4] == '\0' || t[4] == ' '))
                col = k;
        }
        break;
    }
    long step = -1;
    char tail[16384];
    if (col >= 0 && fseek(f, 0, SEEK_END) == 0) {
        long size = ftell(f);
        long from = size > (long)sizeof tail - 1 ? size - (long)sizeof tail + 1 : 0;
        fseek(f, from, SEEK_SET);
        size_t n = fread(tail, 1, sizeof tail - 1, f);
        tail[n] = '\0';
        /* a row is complete when its newline was written */
        char *end = strrchr(tail, '\n');
        if (end) {
            *end = '\0';
            char *start = strrchr(tail, '\n');
            if (start || from == 0) {
                char *row = start ? start + 1 : tail;
                int k = 0;
                char *save = NULL, *t = strtok_r(row, ",\r", &save);
                while (t && k < col) {
                    t = strtok_r(NULL, ",\r", &save);
                    k++;
                }
                char *num_end = NULL;
                double v = t ? strtod(t, &num_end) : NAN;
                if (t && num_end != t && isfinite(v) && v == floor(v) && fabs(v) < 1e15)
                    step = (long)v;
            }
        }
    }
    fclose(f);
    return step;
}

/* Whether a failed job failed because its file system is full or gone
 * read-only (why says so): that is the machine's fault, not the job's. */
static int disk_trouble(const char *dir, const char *stderr_tail, char *why, size_t len)
{
    static const char *const words[] = {"No space left on device", "Disk quota exceeded",
                                        "Read-only file system", "Input/output error"};
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++)
        if (strstr(stderr_tail, words[i])) {
            snprintf(why, len, "the solver reported '%s' in %s", words[i], dir);
            return 1;
        }
    struct statvfs sv;
    if (statvfs(dir, &sv) == 0 && (sv.f_bavail == 0 || (sv.f_files > 0 && sv.f_favail == 0))) {
        snprintf(why, len, "no space left on the file system of %s", dir);
        return 1;
    }
    return 0;
}

void outcome_collect(struct outcome *o, const char *dir, const struct exit_info *x)
{
    double t0 = sys_mono();
    char path[4096 + 32];
    snprintf(path, sizeof path, "%s/stderr", dir);
    outcome_file_tail(path, 20, o->stderr_tail, sizeof o->stderr_tail);
    json_t *res = read_result(dir);
    const char *rstatus = res ? json_string_value(json_object_get(res, "status")) : NULL;
    const char *rmsg = res ? json_string_value(json_object_get(res, "message")) : NULL;
    json_t *prov = res ? json_object_get(res, "provenance") : NULL;
    if (prov) {
        const char *v = json_string_value(json_object_get(prov, "version"));
        const char *g = json_string_value(json_object_get(prov, "git_hash"));
        snprintf(o->solver_version, sizeof o->solver_version, "%s", v ? v : "");
        snprintf(o->solver_git, sizeof o->solver_git, "%s", g ? g : "");
    }
    json_t *rfs = res ? json_object_get(res, "restarted_from_step") : NULL;
    o->resumed_from_step = json_is_integer(rfs) ? (long)json_integer_value(rfs) : -1;
    json_t *metrics = res ? json_object_get(res, "metrics") : NULL;
    if (json_is_object(metrics))
        o->metrics = json_incref(metrics);
    json_t *series = res ? json_object_get(res, "series") : NULL;
    if (json_is_object(series))
        o->series = json_incref(series);
    const char *tail_line = last_line(o->stderr_tail);
    int st = x->wait_status;
    o->exit_code = -1;
    o->signal = 0;
    if (WIFEXITED(st))
        o->exit_code = WEXITSTATUS(st);
    else if (WIFSIGNALED(st))
        o->signal = WTERMSIG(st);
    char sname[32];
    o->failure = FC_JOB;
    if (x->cancelled) {
        o->status = RS_CANCELLED;
        o->failure = FC_NONE;
        snprintf(o->message, sizeof o->message, "cancelled: the runner was asked to stop");
    } else if (x->timed_out) {
        o->status = RS_TIMEOUT;
        snprintf(o->message, sizeof o->message,
                 "timeout: killed (process group) after the limit of %g s", x->timeout);
    } else if (x->exec_failed || o->exit_code == 127) {
        /* exec failed, or the child could not enter the study's directory */
        o->status = RS_CANCELLED;
        o->failure = FC_INFRA;
        snprintf(o->message, sizeof o->message, "could not start the solver: %s",
                 tail_line[0] ? tail_line : "exit 127 (command not found?)");
    } else if (o->signal) {
        o->status = RS_CRASHED;
        snprintf(o->message, sizeof o->message, "crashed: killed by signal %d (%s)", o->signal,
                 outcome_signal_name(o->signal, sname, sizeof sname));
    } else if (o->exit_code == 4 || (rstatus && strcmp(rstatus, "diverged") == 0)) {
        o->status = RS_DIVERGED;
        snprintf(o->message, sizeof o->message, "%s", rmsg ? rmsg : tail_line);
    } else if (o->exit_code > 128 && o->exit_code <= 128 + 64) {
        /* a launcher (mpirun, a shell) reports a child killed by signal n
         * as exit 128 + n, and the child had no chance to say anything */
        o->status = RS_FAILED;
        int sig = o->exit_code - 128;
        snprintf(o->message, sizeof o->message,
                 "exit %d (128 + %d: what it ran was killed by signal %d (%s))%s%s", o->exit_code,
                 sig, sig, outcome_signal_name(sig, sname, sizeof sname),
                 (rmsg || tail_line[0]) ? ": " : "", rmsg ? rmsg : tail_line);
    } else if (o->exit_code != 0) {
        o->status = RS_FAILED;
        snprintf(o->message, sizeof o->message, "exit %d: %s", o->exit_code,
                 rmsg ? rmsg : tail_line);
    } else if (!res) {
        o->status = RS_FAILED;
        snprintf(o->message, sizeof o->message, "exit 0 but no readable result.json");
    } else if (!rstatus || strcmp(rstatus, "ok") != 0) {
        o->status = RS_FAILED;
        snprintf(o->message, sizeof o->message, "result.json status '%s': %s",
                 rstatus ? rstatus : "(none)", rmsg ? rmsg : "");
    } else {
        o->status = RS_DONE;
        o->failure = FC_NONE;
        o->message[0] = '\0';
    }
    char why[4096 + 128];
    if (o->status == RS_FAILED && disk_trouble(dir, o->stderr_tail, why, sizeof why)) {
        char was[OUTCOME_MSG_MAX];
        snprintf(was, sizeof was, "%s", o->message);
        o->status = RS_CANCELLED;
        o->failure = FC_INFRA;
        snprintf(o->message, sizeof o->message, "disk trouble: %s (%s)", why, was);
    }
    o->last_step = o->status == RS_DONE ? -1 : thermo_last_step(dir);
    json_decref(res);
    if (collect_artifacts(o, dir) != 0) {
        /* the runner's trouble, not the job's: the attempt is called off and
         * runs again */
        o->status = RS_CANCELLED;
        o->failure = FC_INFRA;
        snprintf(o->message, sizeof o->message, "out of memory (listing the files of %s)", dir);
    }
    o->collect_s = sys_mono() - t0;
}

void outcome_free(struct outcome *o)
{
    json_decref(o->metrics);
    json_decref(o->series);
    o->series = NULL;
    free(o->artifacts);
    o->metrics = NULL;
    o->artifacts = NULL;
    o->nartifacts = 0;
}

/* A JSON string of s, which json_pack's "s" refuses unless it is UTF-8:
 * bytes that are not (a character cut by a truncation to a fixed buffer,
 * binary output on stderr) become '?'. */
static json_t *jstr(const char *s)
{
    json_t *j = json_string(s);
    if (j)
        return j;
    size_t n = strlen(s), k = 0;
    char *t = mem_alloc(n + 1);
    if (!t)
        return NULL;
    for (size_t i = 0; i < n;) {
        unsigned char c = (unsigned char)s[i];
        size_t len = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3
                                  : (c & 0xF8) == 0xF0 ? 4 : 0;
        json_t *one = len > 1 && i + len <= n ? json_stringn(s + i, len) : NULL;
        if (len == 1 || one) {
            memcpy(t + k, s + i, len);
            k += len;
            i += len;
        } else {
            t[k++] = '?';
            i++;
        }
        json_decref(one);
    }
    t[k] = '\0';
    j = json_string(t);
    free(t);
    return j;
}

json_t *outcome_to_json(const struct outcome *o)
{
    json_t *arts = json_array();
    for (int i = 0; i < o->nartifacts; i++) {
        const struct artifact *a = &o->artifacts[i];
        json_array_append_new(arts, json_pack("{s:o, s:s, s:I, s:s}", "path", jstr(a->path),
                                              "kind", a->kind, "bytes", (json_int_t)a->bytes,
                                              "sha256", a->sha256));
    }
    json_t *j = json_pack("{s:i, s:i, s:i, s:o, s:f, s:f, s:f, s:f, s:i, s:o, s:o, s:o, s:o, s:O?, s:o, s:i, s:I}",
                     "status", (int)o->status, "exit_code", o->exit_code, "signal", o->signal,
                     "message", jstr(o->message), "started", o->started, "finished", o->finished,
                     "wall_s", o->wall_s, "peak_rss_mib", o->peak_rss_mib, "pid", o->pid, "host",
                     jstr(o->host), "stderr_tail", jstr(o->stderr_tail), "solver_version",
                     jstr(o->solver_version), "solver_git", jstr(o->solver_git), "metrics",
                     o->metrics, "artifacts", arts, "failure", (int)o->failure, "last_step",
                     (json_int_t)o->last_step);
    if (j) {
        json_object_set_new(j, "collect_s", json_real(o->collect_s));
        json_object_set_new(j, "resumed_from_step", json_integer(o->resumed_from_step));
        if (o->series)
            json_object_set(j, "series", o->series);
    }
    return j;
}

#define COPY_STR(dst, obj, key)                                                                   \
    do {                                                                                          \
        const char *v_ = json_string_value(json_object_get(obj, key));                            \
        snprintf(dst, sizeof dst, "%s", v_ ? v_ : "");                                            \
    } while (0)

int outcome_from_json(struct outcome *o, const json_t *j, struct err *e)
{
    memset(o, 0, sizeof *o);
    json_t *status = json_object_get(j, "status");
    if (!json_is_integer(status) || json_integer_value(status) < RS_DONE ||
        json_integer_value(status) > RS_CANCELLED)
        return err_set(e, ERR_RUNTIME, "outcome message without a valid status");
    o->status = (enum run_status)json_integer_value(status);
    json_int_t fc = json_integer_value(json_object_get(j, "failure"));
    o->failure = fc >= FC_NONE && fc <= FC_DETERMINISTIC ? (enum failure_class)fc : FC_JOB;
    json_t *ls = json_object_get(j, "last_step");
    o->last_step = json_is_integer(ls) ? (long)json_integer_value(ls) : -1;
    json_t *rf = json_object_get(j, "resumed_from_step");
    o->resumed_from_step = json_is_integer(rf) ? (long)json_integer_value(rf) : -1;
    o->exit_code = (int)json_integer_value(json_object_get(j, "exit_code"));
    o->signal = (int)json_integer_value(json_object_get(j, "signal"));
    o->started = json_number_value(json_object_get(j, "started"));
    o->finished = json_number_value(json_object_get(j, "finished"));
    o->wall_s = json_number_value(json_object_get(j, "wall_s"));
    o->peak_rss_mib = json_number_value(json_object_get(j, "peak_rss_mib"));
    o->collect_s = json_number_value(json_object_get(j, "collect_s"));
    o->pid = (int)json_integer_value(json_object_get(j, "pid"));
    COPY_STR(o->message, j, "message");
    COPY_STR(o->host, j, "host");
    COPY_STR(o->stderr_tail, j, "stderr_tail");
    COPY_STR(o->solver_version, j, "solver_version");
    COPY_STR(o->solver_git, j, "solver_git");
    json_t *m = json_object_get(j, "metrics");
    if (json_is_object(m))
        o->metrics = json_incref(m);
    json_t *ser = json_object_get(j, "series");
    if (json_is_object(ser))
        o->series = json_incref(ser);
    json_t *arts = json_object_get(j, "artifacts");
    size_t n = json_array_size(arts);
    if (n) {
        o->artifacts = mem_calloc(n, sizeof *o->artifacts);
        if (!o->artifacts) {
            outcome_free(o);
            return err_nomem(e, "artifacts");
        }
        for (size_t i = 0; i < n; i++) {
            json_t *a = json_array_get(arts, i);
            struct artifact *x = &o->artifacts[i];
            COPY_STR(x->path, a, "path");
            COPY_STR(x->kind, a, "kind");
            COPY_STR(x->sha256, a, "sha256");
            x->bytes = (long long)json_integer_value(json_object_get(a, "bytes"));
        }
        o->nartifacts = (int)n;
    }
    return 0;
}
