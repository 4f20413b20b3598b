/* slurm_spec: the study's Slurm resources, read, checked and resolved per job. */
#include "slurm_spec.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"

static const char *const res_keys[SR_COUNT] = {"partition", "nodes",   "ntasks",
                                               "cpus_per_task", "mem", "time",
                                               "account",   "qos",     "constraint"};
static const char *const res_options[SR_COUNT] = {"--partition", "--nodes",   "--ntasks",
                                                  "--cpus-per-task", "--mem", "--time",
                                                  "--account",   "--qos",     "--constraint"};

const char *slurm_res_option(enum slurm_res r)
{
    return res_options[r];
}

__attribute__((format(printf, 4, 5))) static int fail(const struct study *s, const char *key,
                                                      struct err *e, const char *fmt, ...)
{
    char what[ERR_MSG_MAX / 2], loc[STUDY_PATH_MAX + 32];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    study_where(s, key, loc, sizeof loc);
    return err_set(e, ERR_INPUT, "%s: %s: %s", loc, key, what);
}

long slurm_time_seconds(const char *t)
{
    /* minutes | M:S | H:M:S | D-H | D-H:M | D-H:M:S (sbatch --time) */
    long f[4] = {0};
    int nf = 0, day = 0;
    const char *p = t;
    if (!*p)
        return -1;
    for (;;) {
        if (!isdigit((unsigned char)*p))
            return -1;
        long v = 0;
        int nd = 0;
        while (isdigit((unsigned char)*p) && nd < 9) {
            v = 10 * v + (*p++ - '0');
            nd++;
        }
        if (isdigit((unsigned char)*p) || nf == 4)
            return -1;
        f[nf++] = v;
        if (*p == '\0')
            break;
        if (*p == '-' && nf == 1 && !day) {
            day = 1;
        } else if (*p != ':') {
            return -1;
        }
        p++;
    }
    if (day) {
        /* D-H, D-H:M, D-H:M:S */
        if (nf < 2 || f[1] > 23 || (nf > 2 && f[2] > 59) || (nf > 3 && f[3] > 59))
            return -1;
        return f[0] * 86400 + f[1] * 3600 + (nf > 2 ? f[2] * 60 : 0) + (nf > 3 ? f[3] : 0);
    }
    if (nf == 1)
        return f[0] * 60;
    if (nf == 2)
        return f[1] > 59 ? -1 : f[0] * 60 + f[1];
    if (nf == 3)
        return f[1] > 59 || f[2] > 59 ? -1 : f[0] * 3600 + f[1] * 60 + f[2];
    return -1;
}

void slurm_time_format(long sec, char *out, size_t len)
{
    snprintf(out, len, "%ld-%02ld:%02ld:%02ld", sec / 86400, sec / 3600 % 24, sec / 60 % 60,
             sec % 60);
}

static int all_of(const char *v, const char *extra)
{
    if (!*v)
        return 0;
    for (const char *c = v; *c; c++)
        if (!isalnum((unsigned char)*c) && !strchr(extra, *c))
            return 0;
    return 1;
}

/* A value as the option takes it, into out; 0 or -1 with why. */
static int norm_value(enum slurm_res r, json_t *v, char *out, size_t len, char *why, size_t wl)
{
    char text[SLURM_VALUE_MAX + 8] = "";
    if (json_is_integer(v) && json_integer_value(v) >= 0)
        snprintf(text, sizeof text, "%lld", (long long)json_integer_value(v));
    else if (json_is_string(v) && strlen(json_string_value(v)) < SLURM_VALUE_MAX)
        snprintf(text, sizeof text, "%s", json_string_value(v));
    else {
        snprintf(why, wl, "must be %s",
                 r == SR_NODES || r == SR_NTASKS || r == SR_CPUS_PER_TASK
                     ? "a positive integer"
                     : "a string (or a whole number) shorter than 128 characters");
        return -1;
    }
    switch (r) {
    case SR_NODES:
    case SR_NTASKS:
    case SR_CPUS_PER_TASK: {
        char *end;
        long n = strtol(text, &end, 10);
        if (!all_of(text, "") || *end || n < 1 || n > 1000000) {
            snprintf(why, wl, "'%s' is not a positive integer", text);
            return -1;
        }
        break;
    }
    case SR_MEM: {
        size_t n = strlen(text);
        char last = text[n - 1];
        if (strchr("KMGTkmgt", last))
            text[n - 1] = '\0';
        int ok = all_of(text, "") && strspn(text, "0123456789") == strlen(text);
        if (strchr("KMGTkmgt", last))
            text[n - 1] = (char)toupper((unsigned char)last);
        if (!ok) {
            snprintf(why, wl, "'%s' is not a memory size (digits and an optional K, M, G or T)",
                     text);
            return -1;
        }
        break;
    }
    case SR_TIME: {
        long sec = json_is_integer(v) ? (long)json_integer_value(v) * 60
                                      : slurm_time_seconds(text);
        if (sec <= 0) {
            snprintf(why, wl, "'%s' is not a positive Slurm time (minutes, M:S, H:M:S, D-H, "
                              "D-H:M or D-H:M:S)",
                     text);
            return -1;
        }
        slurm_time_format(sec, text, sizeof text);
        break;
    }
    case SR_PARTITION:
        if (!all_of(text, "_.-,")) {
            snprintf(why, wl, "'%s' is not a partition name (letters, digits, '_', '.', '-'; "
                              "a comma between several)",
                     text);
            return -1;
        }
        break;
    case SR_ACCOUNT:
    case SR_QOS:
        if (!all_of(text, "_.-")) {
            snprintf(why, wl, "'%s' is not a name (letters, digits, '_', '.', '-')", text);
            return -1;
        }
        break;
    case SR_CONSTRAINT:
        if (!all_of(text, "_.-&|,*:[]()!")) {
            snprintf(why, wl, "'%s' is not a constraint (features joined by & | , with [ ] ( ) "
                              "* :, no blanks)",
                     text);
            return -1;
        }
        break;
    case SR_COUNT:
        break;
    }
    snprintf(out, len, "%s", text);
    return 0;
}

int slurm_extra_ok(const char *opt, char *why, size_t len)
{
    /* options cascade sets itself, or that would change what runs */
    static const char *const own[] = {"array",     "output", "error",      "job-name",
                                      "parsable",  "wrap",   "chdir",      "hold",
                                      "dependency", "input", "open-mode",  "test-only",
                                      "export-file", "wait", "batch",      NULL};
    if (strncmp(opt, "--", 2) != 0 || !islower((unsigned char)opt[2])) {
        snprintf(why, len, "'%s' must be a long sbatch option, '--name' or '--name=value'", opt);
        return 0;
    }
    const char *eq = strchr(opt, '=');
    size_t nlen = eq ? (size_t)(eq - opt - 2) : strlen(opt + 2);
    for (size_t i = 0; i < nlen; i++)
        if (!islower((unsigned char)opt[2 + i]) && !isdigit((unsigned char)opt[2 + i]) &&
            opt[2 + i] != '-') {
            snprintf(why, len, "'%s': an option name is lower-case letters, digits and '-'", opt);
            return 0;
        }
    for (int i = 0; own[i]; i++)
        if (strlen(own[i]) == nlen && strncmp(opt + 2, own[i], nlen) == 0) {
            snprintf(why, len, "'%s' is set by cascade itself", opt);
            return 0;
        }
    if (eq && !all_of(eq + 1, "_.,:@%+/=-")) {
        snprintf(why, len, "'%s': the value may hold letters, digits and _ . , : @ %% + / = - "
                           "only (no blanks, quotes, '#', '$', ';' or newlines)",
                 opt);
        return 0;
    }
    return 1;
}

static int axis_of(const struct study *s, const char *path)
{
    for (int a = 0; a < s->naxes; a++)
        if (strcmp(s->axes[a].path, path) == 0)
            return a;
    return -1;
}

static int read_value(struct study *s, enum slurm_res r, json_t *v, struct err *e)
{
    struct slurm_value *sv = &s->slurm.res[r];
    char key[64], why[512];
    snprintf(key, sizeof key, "slurm.%s", res_keys[r]);
    study_where(s, key, sv->where, sizeof sv->where);
    snprintf(sv->where + strlen(sv->where), sizeof sv->where - strlen(sv->where), ": %s", key);
    sv->axis = -1;
    if (!json_is_object(v)) {
        sv->vals = calloc(1, sizeof *sv->vals);
        if (!sv->vals)
            return err_nomem(e, "slurm");
        sv->nvals = 1;
        if (norm_value(r, v, sv->vals[0], sizeof sv->vals[0], why, sizeof why))
            return fail(s, key, e, "%s", why);
        return 0;
    }
    const char *k;
    json_t *x;
    json_object_foreach(v, k, x) if (strcmp(k, "by") && strcmp(k, "values") && strcmp(k, "default"))
    {
        char w[128];
        snprintf(w, sizeof w, "%s.%s", key, k);
        return fail(s, w, e, "unknown key (a resource by a swept key has 'by', 'values' and "
                             "'default')");
    }
    json_t *by = json_object_get(v, "by"), *vals = json_object_get(v, "values");
    if (!json_is_string(by))
        return fail(s, key, e, "'by' must name a swept key of the study");
    sv->axis = axis_of(s, json_string_value(by));
    if (sv->axis < 0) {
        char w[128];
        snprintf(w, sizeof w, "%s.by", key);
        return fail(s, w, e, "'%s' is not a swept key of this study", json_string_value(by));
    }
    size_t want = json_array_size(s->axes[sv->axis].values);
    if (!json_is_array(vals) || json_array_size(vals) != want) {
        char w[128];
        snprintf(w, sizeof w, "%s.values", key);
        return fail(s, w, e, "must be a list of %zu value%s, one per value of %s", want,
                    want == 1 ? "" : "s", json_string_value(by));
    }
    sv->vals = calloc(want, sizeof *sv->vals);
    if (!sv->vals)
        return err_nomem(e, "slurm");
    sv->nvals = (int)want;
    for (size_t i = 0; i < want; i++)
        if (norm_value(r, json_array_get(vals, i), sv->vals[i], sizeof sv->vals[i], why,
                       sizeof why)) {
            char w[128];
            snprintf(w, sizeof w, "%s.values[%zu]", key, i);
            return fail(s, w, e, "%s", why);
        }
    json_t *d = json_object_get(v, "default");
    if (d && norm_value(r, d, sv->dflt, sizeof sv->dflt, why, sizeof why)) {
        char w[128];
        snprintf(w, sizeof w, "%s.default", key);
        return fail(s, w, e, "%s", why);
    }
    return 0;
}

int slurm_spec_read(struct study *s, json_t *node, struct err *e)
{
    struct slurm_spec *sp = &s->slurm;
    memset(sp, 0, sizeof *sp);
    for (int r = 0; r < SR_COUNT; r++)
        sp->res[r].axis = -1;
    sp->poll_s = 10;
    if (!node || json_is_null(node))
        return 0;
    if (!json_is_object(node))
        return fail(s, "slurm", e, "must be a mapping of resources");
    const char *k;
    json_t *v;
    json_object_foreach(node, k, v)
    {
        char key[160];
        snprintf(key, sizeof key, "slurm.%s", k);
        int r = 0;
        while (r < SR_COUNT && strcmp(k, res_keys[r]) != 0)
            r++;
        int rc = 0;
        if (r < SR_COUNT) {
            rc = read_value(s, (enum slurm_res)r, v, e);
        } else if (strcmp(k, "poll") == 0) {
            if (!json_is_number(v) || json_number_value(v) < 0.1 || json_number_value(v) > 3600)
                rc = fail(s, key, e, "must be seconds between 0.1 and 3600");
            else
                sp->poll_s = json_number_value(v);
        } else if (strcmp(k, "max_submit") == 0) {
            if (!json_is_integer(v) || json_integer_value(v) < 1)
                rc = fail(s, key, e, "must be a positive integer");
            else
                sp->max_submit = (long)json_integer_value(v);
        } else if (strcmp(k, "extra") == 0) {
            if (!json_is_array(v) || json_array_size(v) > SLURM_EXTRA_MAX)
                rc = fail(s, key, e, "must be a list of at most %d sbatch options",
                          SLURM_EXTRA_MAX);
            size_t i;
            json_t *o;
            json_array_foreach(v, i, o)
            {
                char w[192], why[512];
                snprintf(w, sizeof w, "%s[%zu]", key, i);
                if (rc)
                    break;
                if (!json_is_string(o) || strlen(json_string_value(o)) >= SLURM_VALUE_MAX)
                    rc = fail(s, w, e, "must be an sbatch option shorter than %d characters",
                              SLURM_VALUE_MAX);
                else if (!slurm_extra_ok(json_string_value(o), why, sizeof why))
                    rc = fail(s, w, e, "%s", why);
                else
                    snprintf(sp->extra[sp->nextra++], SLURM_VALUE_MAX, "%s",
                             json_string_value(o));
            }
        } else {
            rc = fail(s, key, e, "unknown key (known: partition, nodes, ntasks, cpus_per_task, "
                                 "mem, time, account, qos, constraint, extra, poll, max_submit)");
        }
        if (rc)
            return rc;
    }
    return 0;
}

void slurm_spec_free(struct slurm_spec *sp)
{
    for (int r = 0; r < SR_COUNT; r++)
        free(sp->res[r].vals);
    memset(sp, 0, sizeof *sp);
}

void slurm_spec_job(const struct study *s, long seq, struct slurm_job_res *jr)
{
    memset(jr, 0, sizeof *jr);
    long idx[64] = {0};
    if (seq >= 0 && s->ngroups <= 64)
        study_job_indices(s, seq, idx);
    for (int r = 0; r < SR_COUNT; r++) {
        const struct slurm_value *sv = &s->slurm.res[r];
        jr->where[r] = sv->where;
        if (!sv->nvals)
            continue;
        const char *v = sv->vals[0];
        if (sv->axis >= 0) {
            if (seq >= 0)
                v = sv->vals[idx[s->axes[sv->axis].group]];
            else if (sv->dflt[0])
                v = sv->dflt;
        }
        snprintf(jr->v[r], sizeof jr->v[r], "%s", v);
    }
    if (!jr->v[SR_CPUS_PER_TASK][0])
        snprintf(jr->v[SR_CPUS_PER_TASK], sizeof jr->v[SR_CPUS_PER_TASK], "%ld", s->threads);
    if (!jr->v[SR_TIME][0] && s->timeout > 0) {
        long sec = (long)s->timeout + (s->timeout > (double)(long)s->timeout);
        slurm_time_format(sec, jr->v[SR_TIME], sizeof jr->v[SR_TIME]);
        jr->where[SR_TIME] = "timeout";
    }
    jr->time_s = jr->v[SR_TIME][0] ? slurm_time_seconds(jr->v[SR_TIME]) : 0;
    jr->ntasks = jr->v[SR_NTASKS][0] ? atol(jr->v[SR_NTASKS]) : 1;
    jr->cpus_per_task = atol(jr->v[SR_CPUS_PER_TASK]);
}
