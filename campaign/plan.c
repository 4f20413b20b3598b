/* plan: expanding a study into solver-resolved jobs. */
#include "plan.h"

#include <stdlib.h>
#include <string.h>

#include "util/canon.h"
#include "util/mem.h"

#define PLAN_MAX_ERRORS 8
#define PLAN_MAX_DEPS 256

struct plan_ctx {
    struct plan *p;
    const struct study *s;
    long first;                          /* plan index of answer line 0 */
    char *errors[PLAN_MAX_ERRORS];   /* the messages */
    char *groups[PLAN_MAX_ERRORS];   /* what makes two messages one (study key + message) */
    int nerrors;
    long nfailed;
    char subst_buf[64];
};

/* --- references ----------------------------------------------------------- */

struct dep_ctx {
    const struct study *s;
    int *deps;
    int ndeps;
};

static int collect_dep(void *ctx, const char *case_path, const char *name)
{
    (void)case_path;
    struct dep_ctx *d = ctx;
    int i = study_prep_index(d->s, name);
    if (i < 0)
        return 0;   /* study_load has checked the names */
    for (int k = 0; k < d->ndeps; k++)
        if (d->deps[k] == i)
            return 0;
    if (d->ndeps < PLAN_MAX_DEPS)
        d->deps[d->ndeps++] = i;
    return 0;
}

static const char *subst_key(void *ctx, const char *name, int is_key)
{
    struct plan_ctx *c = ctx;
    if (is_key)
        return NULL;
    int i = study_prep_index(c->s, name);
    if (i < 0)
        return NULL;
    snprintf(c->subst_buf, sizeof c->subst_buf, "${prep:%s}", c->p->jobs[i].key);
    return c->subst_buf;
}

/* --- errors from the solver -------------------------------------------------- */

/* Where in the study a case path of job j comes from. */
static void locate(const struct plan_ctx *c, long j, const char *case_path, char *loc, size_t llen,
                   char *where, size_t wlen)
{
    const struct study *s = c->s;
    const struct plan_job *job = &c->p->jobs[j];
    const struct study_setting *set = job->prep >= 0 ? s->preps[job->prep].set : s->set;
    int nset = job->prep >= 0 ? s->preps[job->prep].nset : s->nset;
    const struct study_source *base = job->prep >= 0 ? &s->preps[job->prep].base : &s->base;
    long *idx = NULL;
    if (job->sweep >= 0 && s->ngroups > 0) {
        idx = mem_alloc((size_t)s->ngroups * sizeof *idx);
        if (idx)
            study_job_indices(s, job->sweep, idx);
    }
    /* pass 0: the error lies inside an edit; pass 1: an edit lies inside it */
    for (int pass = 0; pass < 2; pass++) {
        for (int a = 0; idx && a < s->naxes; a++) {
            const struct study_axis *ax = &s->axes[a];
            if (pass ? docpath_under(ax->path, case_path) && case_path[0]
                     : docpath_under(case_path, ax->path)) {
                snprintf(where, wlen, "%s[%ld]", ax->where, idx[ax->group]);
                study_where(s, where, loc, llen);
                free(idx);
                return;
            }
        }
        for (int i = 0; i < nset; i++) {
            if (pass ? docpath_under(set[i].path, case_path) && case_path[0]
                     : docpath_under(case_path, set[i].path)) {
                snprintf(where, wlen, "%s", set[i].where);
                study_where(s, where, loc, llen);
                free(idx);
                return;
            }
        }
    }
    free(idx);
    study_source_where(s, base, case_path, loc, llen);
    snprintf(where, wlen, "%s%s%s", base->prefix, base->prefix[0] ? "." : "", case_path);
}

/* `group` identifies the complaint regardless of the value index; when two
 * values of one axis draw the same complaint, the axis itself is blamed
 * (`general`). */
static void add_error(struct plan_ctx *c, const char *text, const char *group, const char *general)
{
    c->nfailed++;
    for (int i = 0; i < c->nerrors; i++) {
        if (strcmp(c->groups[i], group) != 0)
            continue;
        if (strcmp(c->errors[i], text) != 0 && strcmp(c->errors[i], general) != 0) {
            free(c->errors[i]);
            c->errors[i] = mem_strdup(general);
        }
        return;
    }
    if (c->nerrors < PLAN_MAX_ERRORS) {
        c->errors[c->nerrors] = mem_strdup(text);
        c->groups[c->nerrors] = mem_strdup(group);
        c->nerrors++;
    }
}

static void solver_error(struct plan_ctx *c, long j, const char *msg)
{
    /* "<stdin line N>: path: message" or "<stdin line N>:L:C: message" */
    const char *rest = msg;
    if (strncmp(rest, "<stdin line ", 12) == 0) {
        const char *gt = strchr(rest, '>');
        if (gt) {
            rest = gt + 1;
            while (*rest == ':' || (*rest >= '0' && *rest <= '9'))
                rest++;
            while (*rest == ' ')
                rest++;
        }
    }
    char path[DOCPATH_MAX] = "";
    const char *colon = strstr(rest, ": ");
    if (colon && (size_t)(colon - rest) < sizeof path && !memchr(rest, ' ', (size_t)(colon - rest))) {
        memcpy(path, rest, (size_t)(colon - rest));
        path[colon - rest] = '\0';
        if (strcmp(path, "(top level)") == 0)
            path[0] = '\0';
    }
    char loc[STUDY_PATH_MAX + 32], where[STUDY_WHERE_MAX + 64];
    locate(c, j, path, loc, sizeof loc, where, sizeof where);
    char text[ERR_MSG_MAX], group[ERR_MSG_MAX], general[ERR_MSG_MAX];
    snprintf(text, sizeof text, "%s: %s: the solver rejects the case: %s", loc,
             where[0] ? where : "(top level)", rest);
    /* the same study key without a value index */
    char *br = strrchr(where, '[');
    if (br && br[strlen(br) - 1] == ']')
        *br = '\0';
    study_where(c->s, where, loc, sizeof loc);
    snprintf(group, sizeof group, "%s: %s", where, rest);
    snprintf(general, sizeof general, "%s: %s: the solver rejects the case: %s", loc,
             where[0] ? where : "(top level)", rest);
    add_error(c, text, group, general);
}

static int on_answer(void *ctx, long line, json_t *answer, struct err *e)
{
    struct plan_ctx *c = ctx;
    long j = c->first + line;
    struct plan_job *job = &c->p->jobs[j];
    if (!json_is_true(json_object_get(answer, "ok"))) {
        const char *msg = json_string_value(json_object_get(answer, "error"));
        solver_error(c, j, msg ? msg : "rejected without a message");
        return 0;
    }
    const char *key = json_string_value(json_object_get(answer, "key"));
    json_t *cs = json_object_get(answer, "case");
    if (!key || strlen(key) != 16 || !json_is_object(cs))
        return err_set(e, ERR_RUNTIME, "solver resolve: answer %ld lacks key or case", line + 1);
    snprintf(job->key, sizeof job->key, "%s", key);
    job->case_json = canon_json(cs);
    return job->case_json ? 0 : err_nomem(e, "case");
}

/* Write job j's case (references turned into keys) as one line. */
static int write_case(struct plan_ctx *c, long j, FILE *f, struct err *e)
{
    const struct study *s = c->s;
    struct plan_job *job = &c->p->jobs[j];
    long idx[64];
    json_t *doc;
    if (job->sweep >= 0)
        study_job_indices(s, job->sweep, idx);
    int rc = study_job_doc(s, job->prep, job->sweep >= 0 ? idx : NULL, &doc, e);
    if (rc)
        return rc;
    int deps[PLAN_MAX_DEPS];
    struct dep_ctx d = {s, deps, 0};
    docpath_refs_visit(doc, collect_dep, &d);
    if (d.ndeps) {
        job->deps = mem_alloc((size_t)d.ndeps * sizeof *job->deps);
        if (!job->deps) {
            json_decref(doc);
            return err_nomem(e, "dependencies");
        }
        memcpy(job->deps, deps, (size_t)d.ndeps * sizeof *deps);
        job->ndeps = d.ndeps;
        docpath_refs_replace(doc, subst_key, c);
    }
    if (job->sweep >= 0) {
        json_t *params = study_job_params(s, idx);
        job->params_json = canon_json(params);
        json_decref(params);
    } else {
        job->params_json = mem_strdup("{}");
    }
    char *text = canon_json(doc);
    json_decref(doc);
    if (!text || !job->params_json) {
        free(text);
        return err_nomem(e, "case");
    }
    fputs(text, f);
    fputc('\n', f);
    free(text);
    return ferror(f) ? err_set(e, ERR_RUNTIME, "cannot write the cases for the solver") : 0;
}

static int resolve_range(struct plan_ctx *c, const struct solver *sv, long first, long n,
                         struct err *e)
{
    FILE *f = tmpfile();
    if (!f)
        return err_set(e, ERR_RUNTIME, "cannot create a temporary file");
    int rc = 0;
    for (long j = first; j < first + n && !rc; j++)
        rc = write_case(c, j, f, e);
    c->first = first;
    if (!rc)
        rc = solver_resolve(sv, f, n, on_answer, c, e);
    fclose(f);
    return rc;
}

struct key_index {
    const char *key;
    long j;
};

static int cmp_key(const void *a, const void *b)
{
    const struct key_index *x = a, *y = b;
    int c = strcmp(x->key, y->key);
    return c ? c : (x->j > y->j) - (x->j < y->j);
}

static int check_duplicates(struct plan_ctx *c, struct err *e)
{
    struct plan *p = c->p;
    struct key_index *order = mem_alloc((size_t)p->njobs * sizeof *order);
    if (!order)
        return err_nomem(e, "key order");
    for (long j = 0; j < p->njobs; j++)
        order[j] = (struct key_index){p->jobs[j].key, j};
    qsort(order, (size_t)p->njobs, sizeof *order, cmp_key);
    int rc = 0;
    for (long k = 1; k < p->njobs && !rc; k++) {
        long a = order[k - 1].j, b = order[k].j;
        if (strcmp(p->jobs[a].key, p->jobs[b].key) != 0)
            continue;
        char la[512], lb[512], loc[STUDY_PATH_MAX + 32];
        plan_job_label(p, a, la, sizeof la);
        plan_job_label(p, b, lb, sizeof lb);
        const struct study *s = c->s;
        char where[STUDY_WHERE_MAX + 32] = "sweep";
        if (p->jobs[b].sweep >= 0 && p->jobs[a].sweep >= 0) {
            long ia[64], ib[64];
            study_job_indices(s, p->jobs[a].sweep, ia);
            study_job_indices(s, p->jobs[b].sweep, ib);
            for (int x = 0; x < s->naxes; x++)
                if (ia[s->axes[x].group] != ib[s->axes[x].group]) {
                    snprintf(where, sizeof where, "%s[%ld]", s->axes[x].where,
                             ib[s->axes[x].group]);
                    break;
                }
        } else if (p->jobs[b].prep >= 0) {
            snprintf(where, sizeof where, "%s", s->preps[p->jobs[b].prep].where);
        } else if (p->jobs[a].prep >= 0) {
            snprintf(where, sizeof where, "%s", s->preps[p->jobs[a].prep].where);
        }
        study_where(s, where, loc, sizeof loc);
        rc = err_set(e, ERR_INPUT,
                     "%s: %s: duplicate values: jobs '%s' and '%s' resolve to the same case "
                     "(key %s)",
                     loc, where, la, lb, p->jobs[a].key);
    }
    free(order);
    return rc;
}

int plan_build(struct plan *p, const struct study *s, const struct solver *sv, struct err *e)
{
    memset(p, 0, sizeof *p);
    p->study = s;
    if (s->ngroups > 64)
        return err_set(e, ERR_INPUT, "%s: at most 64 sweep factors", s->file);
    p->njobs = s->nprep + s->njobs;
    p->nprep = s->nprep;
    p->jobs = mem_calloc((size_t)p->njobs, sizeof *p->jobs);
    if (!p->jobs)
        return err_nomem(e, "jobs");
    for (long j = 0; j < p->njobs; j++) {
        p->jobs[j].prep = j < s->nprep ? (int)j : -1;
        p->jobs[j].sweep = j < s->nprep ? -1 : j - s->nprep;
    }
    struct plan_ctx c = {p, s, 0, {0}, {0}, 0, 0, ""};
    int rc = 0;
    /* one solver call per preparation job (each may need earlier keys), one for the sweep */
    for (int i = 0; i < s->nprep && !rc && !c.nfailed; i++)
        rc = resolve_range(&c, sv, i, 1, e);
    if (!rc && !c.nfailed)
        rc = resolve_range(&c, sv, s->nprep, s->njobs, e);
    if (!rc && c.nfailed) {
        char msg[ERR_MSG_MAX] = "";
        for (int i = 0; i < c.nerrors; i++) {
            size_t used = strlen(msg);
            snprintf(msg + used, sizeof msg - used, "%s%s", i ? "\n" : "", c.errors[i]);
        }
        long others = c.nfailed - c.nerrors;
        if (others > 0) {
            size_t used = strlen(msg);
            snprintf(msg + used, sizeof msg - used, "\n(%ld job%s in all rejected)", c.nfailed,
                     c.nfailed == 1 ? "" : "s");
        }
        rc = err_set(e, ERR_INPUT, "%s", msg);
    }
    for (int i = 0; i < c.nerrors; i++) {
        free(c.errors[i]);
        free(c.groups[i]);
    }
    if (!rc)
        rc = check_duplicates(&c, e);
    if (rc)
        plan_free(p);
    return rc;
}

void plan_free(struct plan *p)
{
    for (long j = 0; p->jobs && j < p->njobs; j++) {
        free(p->jobs[j].case_json);
        free(p->jobs[j].params_json);
        free(p->jobs[j].deps);
    }
    free(p->jobs);
    memset(p, 0, sizeof *p);
}

void plan_job_label(const struct plan *p, long j, char *out, size_t len)
{
    const struct plan_job *job = &p->jobs[j];
    if (job->prep >= 0) {
        snprintf(out, len, "prep %s", p->study->preps[job->prep].name);
        return;
    }
    const struct study *s = p->study;
    if (s->naxes == 0) {
        snprintf(out, len, "%s", "(base case)");
        return;
    }
    long idx[64];
    study_job_indices(s, job->sweep, idx);
    size_t used = 0;
    out[0] = '\0';
    for (int a = 0; a < s->naxes && used + 1 < len; a++) {
        /* a label only: into a buffer, so it needs no memory (a value that
         * is an object shows as '?' when there is none) */
        char v[256];
        if (canon_json_into(json_array_get(s->axes[a].values, (size_t)idx[s->axes[a].group]), v,
                            sizeof v) != 0)
            snprintf(v, sizeof v, "?");
        int n = snprintf(out + used, len - used, "%s%s=%s", a ? " " : "", s->axes[a].path, v);
        if (n < 0)
            break;
        used += (size_t)n;
        if (used >= len)
            used = len - 1;
    }
}
