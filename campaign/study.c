/* study: reading and checking a study file. */
#include "study.h"

#include <errno.h>
#include <libgen.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/canon.h"
#include "util/cfg.h"
#include "util/mem.h"
#include "util/sha256.h"
#include "util/yamldoc.h"

/* --- locations ------------------------------------------------------------ */

static const struct loc *lookup_up(const struct locmap *m, const char *path, int *is_exact)
{
    char up[STUDY_WHERE_MAX + DOCPATH_MAX];
    snprintf(up, sizeof up, "%s", path);
    *is_exact = 1;
    for (;;) {
        const struct loc *l = m ? locmap_get(m, up) : NULL;
        if (l)
            return l;
        if (!up[0])
            return NULL;
        *is_exact = 0;
        char *dot = strrchr(up, '.');
        char *br = strrchr(up, '[');
        char *cut = dot > br ? dot : br;
        if (cut)
            *cut = '\0';
        else
            up[0] = '\0';
    }
}

static void format_loc(const char *file, const struct loc *l, char *out, size_t len)
{
    if (!l) {
        snprintf(out, len, "%s", file);
        return;
    }
    int line = l->key_line ? l->key_line : l->val_line;
    int col = l->key_line ? l->key_col : l->val_col;
    snprintf(out, len, "%s:%d:%d", file, line, col);
}

void study_where(const struct study *s, const char *where, char *out, size_t len)
{
    int exact;
    format_loc(s->file, lookup_up(s->locs, where, &exact), out, len);
}

void study_source_where(const struct study *s, const struct study_source *src,
                        const char *case_path, char *out, size_t len)
{
    char path[STUDY_WHERE_MAX + DOCPATH_MAX];
    snprintf(path, sizeof path, "%s%s%s", src->prefix, src->prefix[0] && case_path[0] ? "." : "",
             case_path);
    int exact;
    format_loc(src->file, lookup_up(src->view, path, &exact), out, len);
}

__attribute__((format(printf, 4, 5))) static int fail_at(const struct study *s, const char *where,
                                                         struct err *e, const char *fmt, ...)
{
    char what[ERR_MSG_MAX / 2], loc[STUDY_PATH_MAX + 32];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    study_where(s, where, loc, sizeof loc);
    return err_set(e, ERR_INPUT, "%s: %s: %s", loc, where[0] ? where : "(top level)", what);
}

static int line_of(const struct study *s, const char *where)
{
    int exact;
    const struct loc *l = lookup_up(s->locs, where, &exact);
    return l ? (l->key_line ? l->key_line : l->val_line) : 0;
}

/* --- reading the file ----------------------------------------------------- */

static int read_text(const char *path, char **text, size_t *len, struct err *e)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(e, ERR_INPUT, "%s: cannot open study: %s", path, strerror(errno));
    size_t cap = 4096, n = 0;
    char *buf = mem_alloc(cap + 1);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            char *nb = mem_realloc(buf, 2 * cap + 1);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf)
        return err_nomem(e, "study text");
    if (bad) {
        free(buf);
        return err_set(e, ERR_INPUT, "%s: read error", path);
    }
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return 0;
}

static int valid_name(const char *s, size_t max)
{
    size_t n = strlen(s);
    if (n == 0 || n >= max || s[0] == '.' || s[0] == '-')
        return 0;
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
              *s == '_' || *s == '-' || *s == '.'))
            return 0;
    return 1;
}

/* A base case: a file name (relative to the study) or an inline mapping. */
static int read_source(struct study *s, json_t *v, const char *where, struct study_source *src,
                       struct err *e)
{
    memset(src, 0, sizeof *src);
    if (json_is_object(v)) {
        src->doc = json_deep_copy(v);
        snprintf(src->file, sizeof src->file, "%s", s->file);
        snprintf(src->prefix, sizeof src->prefix, "%s", where);
        src->view = s->locs;
        return src->doc ? 0 : err_nomem(e, "base case");
    }
    if (!json_is_string(v) || !json_string_value(v)[0])
        return fail_at(s, where, e, "must be a case file name or an inline case (a mapping)");
    const char *name = json_string_value(v);
    char shown[STUDY_PATH_MAX];
    if (name[0] == '/') {
        snprintf(shown, sizeof shown, "%s", name);
    } else {
        char tmp[STUDY_PATH_MAX];
        snprintf(tmp, sizeof tmp, "%s", s->file);
        const char *d = dirname(tmp);
        if (strcmp(d, ".") == 0)
            snprintf(shown, sizeof shown, "%s", name);
        else
            snprintf(shown, sizeof shown, "%s/%s", d, name);
    }
    FILE *probe = fopen(shown, "r");
    if (!probe)
        return fail_at(s, where, e, "cannot open base case '%s': %s", shown, strerror(errno));
    fclose(probe);
    int rc = yamldoc_load_file(shown, &src->doc, &src->locs, e);
    if (rc)
        return rc;
    snprintf(src->file, sizeof src->file, "%s", shown);
    src->view = src->locs;
    if (!json_is_object(src->doc))
        return err_set(e, ERR_INPUT, "%s: a case must be a mapping of keys to values", shown);
    return 0;
}

static void source_free(struct study_source *src)
{
    json_decref(src->doc);
    locmap_destroy(&src->locs);
    memset(src, 0, sizeof *src);
}

/* `set`: a mapping of case paths to values. */
static int read_settings(struct study *s, json_t *v, const char *where, struct study_setting **out,
                         int *n, struct err *e)
{
    *out = NULL;
    *n = 0;
    if (!v || json_is_null(v))
        return 0;
    if (!json_is_object(v))
        return fail_at(s, where, e, "must be a mapping of case keys (like md.steps) to values");
    size_t cap = json_object_size(v);
    struct study_setting *set = mem_calloc(cap ? cap : 1, sizeof *set);
    if (!set)
        return err_nomem(e, "settings");
    const char *key;
    json_t *val;
    int k = 0;
    json_object_foreach(v, key, val)
    {
        struct study_setting *st = &set[k];
        snprintf(st->where, sizeof st->where, "%s.%s", where, key);
        if (!docpath_valid(key)) {
            /* the message names st->where: before set is freed */
            int rc = fail_at(s, st->where, e,
                             "'%s' is not a case key path (keys joined by dots, like md.timestep)",
                             key);
            for (int i = 0; i < k; i++)
                json_decref(set[i].value);
            free(set);
            return rc;
        }
        snprintf(st->path, sizeof st->path, "%s", key);
        st->value = json_incref(val);
        k++;
    }
    *out = set;
    *n = k;
    for (int i = 0; i < k; i++)
        for (int j = 0; j < i; j++)
            if (docpath_overlap(set[i].path, set[j].path))
                return fail_at(s, set[i].where, e, "overlaps '%s' set at line %d", set[j].path,
                               line_of(s, set[j].where));
    return 0;
}

static void settings_free(struct study_setting *set, int n)
{
    for (int i = 0; i < n; i++)
        json_decref(set[i].value);
    free(set);
}

/* --- sweep axes ----------------------------------------------------------- */

static int add_axis(struct study *s, const char *path, enum axis_kind kind, int group, json_t *values,
                    const char *where, struct err *e)
{
    struct study_axis *grown = mem_realloc(s->axes, (size_t)(s->naxes + 1) * sizeof *grown);
    if (!grown)
        return err_nomem(e, "axes");
    s->axes = grown;
    struct study_axis *a = &s->axes[s->naxes++];
    memset(a, 0, sizeof *a);
    snprintf(a->path, sizeof a->path, "%s", path);
    a->kind = kind;
    a->group = group;
    a->values = json_incref(values);
    snprintf(a->where, sizeof a->where, "%s", where);
    return 0;
}

static int check_axis_list(struct study *s, const char *key, json_t *list, const char *where,
                           int check_dups, struct err *e)
{
    if (!docpath_valid(key))
        return fail_at(s, where, e,
                       "'%s' is not a case key path (keys joined by dots, like md.timestep)", key);
    if (!json_is_array(list))
        return fail_at(s, where, e, "must be a list of values, like [1, 2, 4]");
    if (json_array_size(list) == 0)
        return fail_at(s, where, e, "empty axis: give at least one value");
    if (!check_dups)
        return 0;
    size_t n = json_array_size(list);
    for (size_t i = 1; i < n; i++)
        for (size_t j = 0; j < i; j++)
            if (json_equal(json_array_get(list, i), json_array_get(list, j))) {
                char vw[STUDY_WHERE_MAX + 16], first[STUDY_WHERE_MAX + 16];
                snprintf(vw, sizeof vw, "%s[%zu]", where, i);
                snprintf(first, sizeof first, "%s[%zu]", where, j);
                char *text = canon_json(json_array_get(list, i));
                int rc = fail_at(s, vw, e, "duplicate value %s (also value %zu, line %d)",
                                 text ? text : "?", j + 1, line_of(s, first));
                free(text);
                return rc;
            }
    return 0;
}

static int read_zip_group(struct study *s, json_t *grp, const char *where, int group, struct err *e)
{
    if (!json_is_object(grp) || json_object_size(grp) == 0)
        return fail_at(s, where, e, "a zipped group is a mapping of case keys to lists of equal "
                                    "length");
    const char *key, *first_key = NULL;
    json_t *list;
    size_t len = 0;
    int first_index = s->naxes;
    json_object_foreach(grp, key, list)
    {
        char w[STUDY_WHERE_MAX];
        snprintf(w, sizeof w, "%s.%s", where, key);
        int rc = check_axis_list(s, key, list, w, 0, e);
        if (rc)
            return rc;
        if (!first_key) {
            first_key = key;
            len = json_array_size(list);
        } else if (json_array_size(list) != len) {
            return fail_at(s, w, e, "zipped axes of unequal length: %s has %zu values, %s has %zu",
                           key, json_array_size(list), first_key, len);
        }
        if ((rc = add_axis(s, key, AXIS_ZIP, group, list, w, e)))
            return rc;
    }
    /* the tuples must differ */
    for (size_t i = 1; i < len; i++)
        for (size_t j = 0; j < i; j++) {
            int same = 1;
            for (int a = first_index; a < s->naxes && same; a++)
                same = json_equal(json_array_get(s->axes[a].values, i),
                                  json_array_get(s->axes[a].values, j));
            if (same) {
                char vw[STUDY_WHERE_MAX + 16];
                snprintf(vw, sizeof vw, "%s[%zu]", s->axes[first_index].where, i);
                return fail_at(s, vw, e, "duplicate values: zipped entry %zu repeats entry %zu",
                               i + 1, j + 1);
            }
        }
    return 0;
}

static int read_sweep(struct study *s, struct cfg_obj *root, struct err *e)
{
    struct cfg_obj sw;
    int present, rc;
    if ((rc = cfg_section_opt(root, "sweep", &sw, &present)))
        return rc;
    int group = 0;
    if (present) {
        cfg_allow(&sw, "grid");
        cfg_allow(&sw, "zip");
        if ((rc = cfg_close(&sw)))
            return rc;
        json_t *grid = json_object_get(sw.node, "grid");
        json_t *zip = json_object_get(sw.node, "zip");
        if ((!grid || json_is_null(grid)) && (!zip || json_is_null(zip)))
            return fail_at(s, "sweep", e, "give 'grid' (a cartesian product) and/or 'zip' "
                                          "(lists taken together)");
        if (grid && !json_is_null(grid)) {
            if (!json_is_object(grid))
                return fail_at(s, "sweep.grid", e, "must be a mapping of case keys to value lists");
            const char *key;
            json_t *list;
            json_object_foreach(grid, key, list)
            {
                char w[STUDY_WHERE_MAX];
                snprintf(w, sizeof w, "sweep.grid.%s", key);
                if ((rc = check_axis_list(s, key, list, w, 1, e)) ||
                    (rc = add_axis(s, key, AXIS_GRID, group++, list, w, e)))
                    return rc;
            }
        }
        if (zip && !json_is_null(zip)) {
            if (json_is_object(zip)) {
                if ((rc = read_zip_group(s, zip, "sweep.zip", group++, e)))
                    return rc;
            } else if (json_is_array(zip)) {
                size_t i;
                json_t *g;
                json_array_foreach(zip, i, g)
                {
                    char w[STUDY_WHERE_MAX];
                    snprintf(w, sizeof w, "sweep.zip[%zu]", i);
                    if ((rc = read_zip_group(s, g, w, group++, e)))
                        return rc;
                }
            } else {
                return fail_at(s, "sweep.zip", e, "must be a mapping of case keys to lists of "
                                                  "equal length, or a list of such mappings");
            }
        }
    }
    /* an axis swept twice, or an axis that is also set */
    for (int i = 0; i < s->naxes; i++) {
        for (int j = 0; j < i; j++)
            if (docpath_overlap(s->axes[i].path, s->axes[j].path))
                return fail_at(s, s->axes[i].where, e, "%s is swept twice (also at line %d as %s)",
                               s->axes[i].path, line_of(s, s->axes[j].where), s->axes[j].path);
        for (int j = 0; j < s->nset; j++)
            if (docpath_overlap(s->axes[i].path, s->set[j].path))
                return fail_at(s, s->axes[i].where, e, "%s is both swept and set (set at line %d)",
                               s->axes[i].path, line_of(s, s->set[j].where));
    }
    /* repeats: one more factor, the seed */
    if (s->repeats > 1) {
        for (int i = 0; i < s->naxes; i++)
            if (docpath_overlap(s->axes[i].path, "seed"))
                return fail_at(s, "repeats", e, "repeats set the seed, which is also swept at "
                                                "line %d", line_of(s, s->axes[i].where));
        long seed0 = 1;
        json_t *sv = NULL;
        for (int j = 0; j < s->nset; j++)
            if (strcmp(s->set[j].path, "seed") == 0)
                sv = s->set[j].value;
        if (!sv)
            sv = json_object_get(s->base.doc, "seed");
        if (json_is_integer(sv))
            seed0 = (long)json_integer_value(sv);
        json_t *seeds = json_array();
        for (long r = 0; r < s->repeats; r++)
            json_array_append_new(seeds, json_integer(seed0 + r));
        for (int j = 0; j < s->nset; j++)   /* the repeat axis replaces a fixed seed */
            if (strcmp(s->set[j].path, "seed") == 0) {
                json_decref(s->set[j].value);
                s->set[j] = s->set[--s->nset];
                break;
            }
        rc = add_axis(s, "seed", AXIS_REPEAT, group++, seeds, "repeats", e);
        json_decref(seeds);
        if (rc)
            return rc;
    }
    s->ngroups = group;
    s->group_len = mem_calloc((size_t)(group ? group : 1), sizeof *s->group_len);
    if (!s->group_len)
        return err_nomem(e, "groups");
    for (int i = 0; i < s->naxes; i++)
        s->group_len[s->axes[i].group] = (long)json_array_size(s->axes[i].values);
    s->njobs = 1;
    for (int g = 0; g < group; g++) {
        if (s->njobs > STUDY_MAX_JOBS / s->group_len[g])
            return fail_at(s, "sweep", e, "more than %ld jobs", STUDY_MAX_JOBS);
        s->njobs *= s->group_len[g];
    }
    return 0;
}

/* --- references to preparation jobs ------------------------------------------ */

struct ref_check {
    const struct study *s;
    const char *where_if_set;        /* the study key of a set value / axis value, or NULL */
    const struct study_source *src;  /* else: the base the string is in */
    int allowed_before;              /* prep index limit (exclusive), or -1: any prep */
    int self;                        /* prep index being checked, or -1 */
    int *needs;                      /* out: needs[p] = 1 for referenced preps (or NULL) */
    struct err *e;
};

static int ref_check_one(void *ctx, const char *case_path, const char *name)
{
    struct ref_check *rc = ctx;
    const struct study *s = rc->s;
    int p = study_prep_index(s, name);
    if (p >= 0 && p != rc->self) {
        if (rc->needs)
            rc->needs[p] = 1;
        return 0;
    }
    char loc[STUDY_PATH_MAX + 32];
    if (rc->where_if_set)
        study_where(s, rc->where_if_set, loc, sizeof loc);
    else
        study_source_where(s, rc->src, case_path, loc, sizeof loc);
    const char *w = rc->where_if_set ? rc->where_if_set : case_path;
    if (p >= 0 && p == rc->self)
        return err_set(rc->e, ERR_INPUT, "%s: %s: preparation job '%s' cannot read its own output",
                       loc, w, name);
    return err_set(rc->e, ERR_INPUT, "%s: %s: ${prep.%s}: no preparation job named '%s'%s", loc, w,
                   name, name, s->nprep ? "" : " (the study has no 'prep' section)");
}

static int bad_refs(const struct study *s, const json_t *v, const char *where_if_set,
                    const struct study_source *src, const char *case_path, struct err *e)
{
    if (json_is_string(v)) {
        if (!docpath_has_bad_ref(json_string_value(v)))
            return 0;
        char loc[STUDY_PATH_MAX + 32];
        if (where_if_set)
            study_where(s, where_if_set, loc, sizeof loc);
        else
            study_source_where(s, src, case_path, loc, sizeof loc);
        return err_set(e, ERR_INPUT, "%s: %s: '%s': '${' starts a reference, written ${prep.NAME}",
                       loc, where_if_set ? where_if_set : case_path, json_string_value(v));
    }
    char sub[1024];
    if (json_is_object(v)) {
        const char *k;
        json_t *x;
        json_object_foreach((json_t *)v, k, x)
        {
            snprintf(sub, sizeof sub, "%s%s%s", case_path, case_path[0] ? "." : "", k);
            int rc = bad_refs(s, x, where_if_set, src, sub, e);
            if (rc)
                return rc;
        }
    } else if (json_is_array(v)) {
        size_t i;
        json_t *x;
        json_array_foreach(v, i, x)
        {
            snprintf(sub, sizeof sub, "%s[%zu]", case_path, i);
            int rc = bad_refs(s, x, where_if_set, src, sub, e);
            if (rc)
                return rc;
        }
    }
    return 0;
}

/* Check the references of one case's parts; fills needs[] when given. */
static int check_refs(const struct study *s, const struct study_source *base,
                      const struct study_setting *set, int nset, int self, int *needs,
                      struct err *e)
{
    struct ref_check rc = {s, NULL, base, -1, self, needs, e};
    int r = bad_refs(s, base->doc, NULL, base, "", e);
    if (!r)
        r = docpath_refs_visit(base->doc, ref_check_one, &rc);
    for (int i = 0; !r && i < nset; i++) {
        rc.where_if_set = set[i].where;
        r = bad_refs(s, set[i].value, set[i].where, base, "", e);
        if (!r)
            r = docpath_refs_visit(set[i].value, ref_check_one, &rc);
    }
    return r;
}

static int read_preps(struct study *s, json_t *v, struct err *e)
{
    if (!v || json_is_null(v))
        return 0;
    if (!json_is_object(v) || json_object_size(v) == 0)
        return fail_at(s, "prep", e, "must be a mapping of names to preparation jobs, like "
                                     "equil: {set: {md.steps: 1000}}");
    size_t n = json_object_size(v);
    s->preps = mem_calloc(n, sizeof *s->preps);
    if (!s->preps)
        return err_nomem(e, "preps");
    const char *name;
    json_t *pv;
    int rc = 0;
    json_object_foreach(v, name, pv)
    {
        struct study_prep *p = &s->preps[s->nprep++];
        snprintf(p->where, sizeof p->where, "prep.%s", name);
        if (!valid_name(name, sizeof p->name) || strchr(name, '.'))
            return fail_at(s, p->where, e, "a preparation job name is letters, digits, '_' "
                                           "and '-'");
        snprintf(p->name, sizeof p->name, "%s", name);
        if (!json_is_object(pv))
            return fail_at(s, p->where, e, "must be a mapping with 'base' and/or 'set'");
        struct cfg c = {s->file, s->locs, e, s->dir, 1};
        struct cfg_obj o = {0};
        o.cfg = &c;
        o.node = pv;
        snprintf(o.path, sizeof o.path, "%s", p->where);
        cfg_allow(&o, "base");
        cfg_allow(&o, "set");
        if ((rc = cfg_close(&o)))
            return rc;
        json_t *b = json_object_get(pv, "base");
        char bw[STUDY_WHERE_MAX + 8];
        snprintf(bw, sizeof bw, "%s.base", p->where);
        if (b && !json_is_null(b)) {
            if ((rc = read_source(s, b, bw, &p->base, e)))
                return rc;
        } else {
            p->base.doc = json_deep_copy(s->base.doc);
            snprintf(p->base.file, sizeof p->base.file, "%s", s->base.file);
            snprintf(p->base.prefix, sizeof p->base.prefix, "%s", s->base.prefix);
            p->base.locs = NULL;
            p->base.view = s->base.view;
        }
        char sw[STUDY_WHERE_MAX + 8];
        snprintf(sw, sizeof sw, "%s.set", p->where);
        if ((rc = read_settings(s, json_object_get(pv, "set"), sw, &p->set, &p->nset, e)))
            return rc;
    }
    /* dependency order: a prep may read the output of others, never in a cycle */
    int np = s->nprep;
    int *needs = mem_calloc((size_t)np * (size_t)np, sizeof *needs);
    int *order = mem_calloc((size_t)np, sizeof *order), *placed = mem_calloc((size_t)np, sizeof *placed);
    if (!needs || !order || !placed) {
        free(needs);
        free(order);
        free(placed);
        return err_nomem(e, "prep order");
    }
    for (int i = 0; i < np && !rc; i++)
        rc = check_refs(s, &s->preps[i].base, s->preps[i].set, s->preps[i].nset, i, needs + i * np,
                        e);
    int k = 0;
    while (!rc && k < np) {
        int progress = 0;
        for (int i = 0; i < np; i++) {
            if (placed[i])
                continue;
            int ready = 1;
            for (int j = 0; j < np && ready; j++)
                ready = !needs[i * np + j] || placed[j];
            if (ready) {
                placed[i] = 1;
                order[k++] = i;
                progress = 1;
            }
        }
        if (!progress) {
            for (int i = 0; i < np; i++)
                if (!placed[i]) {
                    rc = fail_at(s, s->preps[i].where, e,
                                 "preparation jobs read each other's output in a cycle");
                    break;
                }
        }
    }
    if (!rc) {
        struct study_prep *sorted = mem_calloc((size_t)np, sizeof *sorted);
        if (!sorted) {
            rc = err_nomem(e, "prep order");
        } else {
            for (int i = 0; i < np; i++)
                sorted[i] = s->preps[order[i]];
            free(s->preps);
            s->preps = sorted;
        }
    }
    free(needs);
    free(order);
    free(placed);
    return rc;
}

static int read_launcher(struct study *s, struct cfg_obj *root, struct err *e)
{
    const char *l;
    int rc = cfg_string(root, "launcher", "local", &l);
    if (rc)
        return rc;
    snprintf(s->launcher, sizeof s->launcher, "%s", l);
    if (strcmp(l, "local") == 0)
        return 0;
    char buf[512];
    snprintf(buf, sizeof buf, "%s", l);
    char *save = NULL;
    char *tok = strtok_r(buf, " \t", &save);
    if (!tok || strcmp(tok, "mpirun") != 0)
        return fail_at(s, "launcher", e, "must be 'local' or 'mpirun -np K [options]'");
    while ((tok = strtok_r(NULL, " \t", &save))) {
        if (strcmp(tok, "-np") == 0 || strcmp(tok, "-n") == 0 || strcmp(tok, "--np") == 0) {
            char *num = strtok_r(NULL, " \t", &save), *end;
            long np = num ? strtol(num, &end, 10) : 0;
            if (!num || *end || np < 1 || np > 100000)
                return fail_at(s, "launcher", e, "-np needs a positive process count");
            s->mpirun_np = (int)np;
        }
    }
    if (!s->mpirun_np)
        return fail_at(s, "launcher", e, "'mpirun' needs '-np K'");
    return 0;
}

static int read_metrics(struct study *s, struct cfg_obj *root, struct err *e)
{
    cfg_allow(root, "metrics");
    json_t *v = json_object_get(root->node, "metrics");
    if (!v || json_is_null(v) || (json_is_string(v) && strcmp(json_string_value(v), "all") == 0))
        return 0;
    if (!json_is_array(v) || json_array_size(v) == 0)
        return fail_at(s, "metrics", e, "must be 'all' or a list of metric names from result.json");
    s->nmetrics = (int)json_array_size(v);
    s->metrics = mem_calloc((size_t)s->nmetrics, sizeof *s->metrics);
    if (!s->metrics)
        return err_nomem(e, "metrics");
    for (int i = 0; i < s->nmetrics; i++) {
        json_t *m = json_array_get(v, (size_t)i);
        char w[64];
        snprintf(w, sizeof w, "metrics[%d]", i);
        if (!json_is_string(m) || !json_string_value(m)[0])
            return fail_at(s, w, e, "must be a metric name");
        for (int j = 0; j < i; j++)
            if (strcmp(s->metrics[j], json_string_value(m)) == 0)
                return fail_at(s, w, e, "'%s' is listed twice", json_string_value(m));
        s->metrics[i] = mem_strdup(json_string_value(m));
        if (!s->metrics[i])
            return err_nomem(e, "metrics");
    }
    return 0;
}

/* `series:` -- the result.json series to keep in the database (none by
 * default: a long run's thermo series would swell it). */
static int read_series(struct study *s, struct cfg_obj *root, struct err *e)
{
    cfg_allow(root, "series");
    json_t *v = json_object_get(root->node, "series");
    if (!v || json_is_null(v))
        return 0;
    if (!json_is_array(v) || json_array_size(v) == 0)
        return fail_at(s, "series", e, "must be a list of series names from result.json");
    s->nseries = (int)json_array_size(v);
    s->series = mem_calloc((size_t)s->nseries, sizeof *s->series);
    if (!s->series)
        return err_nomem(e, "series");
    for (int i = 0; i < s->nseries; i++) {
        json_t *m = json_array_get(v, (size_t)i);
        char w[64];
        snprintf(w, sizeof w, "series[%d]", i);
        if (!json_is_string(m) || !json_string_value(m)[0])
            return fail_at(s, w, e, "must be a series name");
        for (int j = 0; j < i; j++)
            if (strcmp(s->series[j], json_string_value(m)) == 0)
                return fail_at(s, w, e, "'%s' is listed twice", json_string_value(m));
        s->series[i] = mem_strdup(json_string_value(m));
        if (!s->series[i])
            return err_nomem(e, "series");
    }
    return 0;
}

/* --- report settings against the study ------------------------------------ */

static int swept(const struct study *s, const char *path)
{
    for (int i = 0; i < s->naxes; i++)
        if (strcmp(s->axes[i].path, path) == 0)
            return 1;
    return 0;
}

/* Whether a metric may be recorded: listed, or the study records all. */
static int recorded(const struct study *s, const char *metric)
{
    if (!s->metrics)
        return 1;
    for (int i = 0; i < s->nmetrics; i++)
        if (strcmp(s->metrics[i], metric) == 0)
            return 1;
    return 0;
}

static int check_report(const struct study *s, struct err *e)
{
    const struct report_spec *r = &s->report;
    if (r->res_mode == RES_AXIS && (!swept(s, r->res_axis) || strcmp(r->res_axis, "seed") == 0))
        return fail_at(s, "report.resolution", e, "'%s' is not a swept key of this study",
                       r->res_axis);
    for (int i = 0; i < r->nmetrics; i++)
        if (!recorded(s, r->metrics[i]))
            return fail_at(s, "report.metrics", e, "'%s' is not among the study's metrics",
                           r->metrics[i]);
    for (int i = 0; i < r->naxes; i++)
        if (!swept(s, r->axes[i].path)) {
            char w[STUDY_WHERE_MAX];
            snprintf(w, sizeof w, "report.axes.%s", r->axes[i].path);
            return fail_at(s, w, e, "'%s' is not a swept key of this study", r->axes[i].path);
        }
    for (int i = 0; i < r->nfits; i++) {
        const struct rspec_fit *f = &r->fits[i];
        if (!recorded(s, f->metric))
            return fail_at(s, f->where, e, "metric '%s' is not among the study's metrics",
                           f->metric);
        if (!swept(s, f->against) && !(s->metrics && recorded(s, f->against)) && s->metrics)
            return fail_at(s, f->where, e, "against: '%s' is neither a swept key nor one of the "
                                           "study's metrics",
                           f->against);
        if (f->along[0] && !swept(s, f->along))
            return fail_at(s, f->where, e, "along: '%s' is not a swept key of this study",
                           f->along);
    }
    for (int i = 0; i < r->ntols; i++)
        if (!recorded(s, r->tols[i].metric)) {
            char w[STUDY_WHERE_MAX];
            snprintf(w, sizeof w, "regress.tolerances.%s", r->tols[i].metric);
            return fail_at(s, w, e, "'%s' is not among the study's metrics", r->tols[i].metric);
        }
    return 0;
}

/* The refine section against the sweep: the axis is swept in a factor of
 * its own (or with keys that follow it), with three or more start levels. */
static int check_refine(struct study *s, struct err *e)
{
    struct refine_spec *r = &s->refine;
    if (!r->on)
        return 0;
    if (!r->axis[0]) {
        if (s->report.res_mode != RES_AXIS)
            return fail_at(s, "refine", e, "name the axis to refine: refine.axis or "
                                           "report.resolution");
        snprintf(r->axis, sizeof r->axis, "%s", s->report.res_axis);
    }
    if (s->report.res_mode == RES_NONE ||
        (s->report.res_mode == RES_AXIS && strcmp(s->report.res_axis, r->axis) != 0))
        return fail_at(s, "refine.axis", e, "'%s' is not the report's resolution axis ('%s')",
                       r->axis, s->report.res_mode == RES_NONE ? "none" : s->report.res_axis);
    int ax = -1;
    for (int i = 0; i < s->naxes; i++)
        if (strcmp(s->axes[i].path, r->axis) == 0)
            ax = i;
    if (ax < 0 || s->axes[ax].kind == AXIS_REPEAT || strcmp(r->axis, "seed") == 0)
        return fail_at(s, "refine.axis", e, "'%s' is not a swept key of this study", r->axis);
    size_t nstart = json_array_size(s->axes[ax].values);
    if (nstart < 3)
        return fail_at(s, "refine.axis", e, "%s has %zu value%s: refinement starts from three or "
                                            "more levels (the sweep's values)",
                       r->axis, nstart, nstart == 1 ? "" : "s");
    if ((long)nstart > r->max_levels)
        return fail_at(s, "refine.max_levels", e, "%ld is fewer than the %zu start levels",
                       r->max_levels, nstart);
    for (int i = 0; i < s->naxes; i++) {
        if (i == ax || s->axes[i].group != s->axes[ax].group)
            continue;
        int f = -1;
        for (int k = 0; k < r->nfollow; k++)
            if (strcmp(r->follow[k].path, s->axes[i].path) == 0)
                f = k;
        if (f < 0)
            return fail_at(s, "refine", e, "%s is zipped with %s: say how it follows the refined "
                                           "axis (refine.follow: {%s: inverse | value | same})",
                           s->axes[i].path, r->axis, s->axes[i].path);
    }
    for (int k = 0; k < r->nfollow; k++) {
        int ok = 0;
        for (int i = 0; i < s->naxes; i++)
            ok |= i != ax && s->axes[i].group == s->axes[ax].group &&
                  strcmp(s->axes[i].path, r->follow[k].path) == 0;
        if (!ok) {
            char w[STUDY_WHERE_MAX];
            snprintf(w, sizeof w, "refine.follow.%s", r->follow[k].path);
            return fail_at(s, w, e, "'%s' is not zipped with %s", r->follow[k].path, r->axis);
        }
    }
    for (int k = 0; k < r->nmetrics; k++)
        if (!recorded(s, r->metrics[k]))
            return fail_at(s, "refine", e, "metric '%s' is not among the study's metrics",
                           r->metrics[k]);
    return 0;
}

static int study_read(struct study *s, struct err *e)
{
    struct cfg c = {s->file, s->locs, e, s->dir, 1};
    struct cfg_obj root;
    int rc = cfg_root(&c, s->doc, &root);
    if (rc)
        return rc;
    const char *name, *desc;
    if ((rc = cfg_string(&root, "name", NULL, &name)) ||
        (rc = cfg_string(&root, "description", "", &desc)))
        return rc;
    if (!valid_name(name, sizeof s->name))
        return fail_at(s, "name", e, "'%s': a study name is letters, digits, '_', '-' and '.' "
                                     "(it names the directory runs/<name>/)", name);
    snprintf(s->name, sizeof s->name, "%s", name);
    s->description = mem_strdup(desc);
    if (!s->description)
        return err_nomem(e, "description");
    cfg_allow(&root, "base");
    json_t *base = json_object_get(s->doc, "base");
    if (!base || json_is_null(base))
        return fail_at(s, "", e, "missing required key 'base' (a case file name or an inline case)");
    if ((rc = read_source(s, base, "base", &s->base, e)))
        return rc;
    cfg_allow(&root, "set");
    if ((rc = read_settings(s, json_object_get(s->doc, "set"), "set", &s->set, &s->nset, e)))
        return rc;
    if ((rc = cfg_int(&root, "repeats", 1, CFG_RANGE(1, 100000), &s->repeats)) ||
        (rc = read_sweep(s, &root, e)))
        return rc;
    cfg_allow(&root, "prep");
    if ((rc = read_preps(s, json_object_get(s->doc, "prep"), e)))
        return rc;
    if ((rc = check_refs(s, &s->base, s->set, s->nset, -1, NULL, e)))
        return rc;
    for (int i = 0; i < s->naxes; i++) {
        size_t k;
        json_t *v;
        json_array_foreach(s->axes[i].values, k, v)
        {
            char w[STUDY_WHERE_MAX + 16];
            snprintf(w, sizeof w, "%s[%zu]", s->axes[i].where, k);
            struct study_setting one = {{0}, v, {0}};
            snprintf(one.where, sizeof one.where, "%s", w);
            struct study_source none = {0};
            if ((rc = check_refs(s, &none, &one, 1, -1, NULL, e)))
                return rc;
        }
    }
    if ((rc = read_metrics(s, &root, e)) || (rc = read_series(s, &root, e)) || (rc = read_launcher(s, &root, e)) ||
        (rc = cfg_int(&root, "threads", 1, CFG_RANGE(1, 1024), &s->threads)) ||
        (rc = cfg_real(&root, "timeout", 0.0, CFG_GE(0), &s->timeout)) ||
        (rc = cfg_int(&root, "retries", 0, CFG_RANGE(0, 100), &s->retries)))
        return rc;
    static const char *const backends[] = {"local", "slurm", NULL};
    int backend = 0;
    if ((rc = cfg_enum(&root, "backend", "local", backends, &backend)) ||
        (rc = cfg_int(&root, "max_running", 0, CFG_RANGE(0, 1000000), &s->max_running)))
        return rc;
    s->backend = backend ? STUDY_BACKEND_SLURM : STUDY_BACKEND_LOCAL;
    cfg_allow(&root, "slurm");
    if ((rc = slurm_spec_read(s, json_object_get(s->doc, "slurm"), e)))
        return rc;
    if (s->backend == STUDY_BACKEND_SLURM && s->mpirun_np)
        return fail_at(s, "launcher", e, "with backend slurm, ask for MPI ranks with "
                                         "slurm.ntasks (srun starts them), not mpirun");
    if ((rc = report_spec_read(&root, &s->report)) || (rc = check_report(s, e)))
        return rc;
    if ((rc = refine_spec_read(&root, &s->refine)) || (rc = check_refine(s, e)))
        return rc;
    return cfg_close(&root);
}

int study_load(struct study *s, const char *path, struct err *e)
{
    memset(s, 0, sizeof *s);
    snprintf(s->file, sizeof s->file, "%s", path);
    int rc = read_text(path, &s->text, &s->textlen, e);
    if (rc)
        return rc;
    sha256_hex(s->text, s->textlen, s->hash);
    if (!realpath(path, s->abspath)) {
        rc = err_set(e, ERR_INPUT, "%s: %s", path, strerror(errno));
        study_free(s);
        return rc;
    }
    char tmp[STUDY_PATH_MAX];
    snprintf(tmp, sizeof tmp, "%s", s->abspath);
    snprintf(s->dir, sizeof s->dir, "%s", dirname(tmp));
    rc = yamldoc_load_string(s->text, s->textlen, s->file, &s->doc, &s->locs, e);
    if (!rc)
        rc = study_read(s, e);
    if (rc)
        study_free(s);
    return rc;
}

void study_free(struct study *s)
{
    free(s->text);
    json_decref(s->doc);
    locmap_destroy(&s->locs);
    free(s->description);
    source_free(&s->base);
    settings_free(s->set, s->nset);
    for (int i = 0; i < s->naxes; i++)
        json_decref(s->axes[i].values);
    free(s->axes);
    free(s->group_len);
    for (int i = 0; i < s->nprep; i++) {
        source_free(&s->preps[i].base);
        settings_free(s->preps[i].set, s->preps[i].nset);
    }
    free(s->preps);
    for (int i = 0; i < s->nmetrics; i++)
        free(s->metrics[i]);
    free(s->metrics);
    for (int i = 0; i < s->nseries; i++)
        free(s->series[i]);
    free(s->series);
    report_spec_free(&s->report);
    slurm_spec_free(&s->slurm);
    memset(s, 0, sizeof *s);
}

/* --- jobs ----------------------------------------------------------------- */

void study_job_indices(const struct study *s, long seq, long *idx)
{
    for (int g = s->ngroups - 1; g >= 0; g--) {
        idx[g] = seq % s->group_len[g];
        seq /= s->group_len[g];
    }
}

int study_prep_index(const struct study *s, const char *name)
{
    for (int i = 0; i < s->nprep; i++)
        if (strcmp(s->preps[i].name, name) == 0)
            return i;
    return -1;
}

static int apply(const struct study *s, json_t *doc, const char *path, json_t *value,
                 const char *where, struct err *e)
{
    char bad[DOCPATH_MAX];
    json_t *copy = json_deep_copy(value);
    if (!copy)
        return err_nomem(e, "case");
    if (docpath_set(doc, path, copy, bad, sizeof bad) != 0)
        return fail_at(s, where, e, "cannot set %s: '%s' is not a mapping in the base case", path,
                       bad);
    return 0;
}

int study_job_doc(const struct study *s, int prep, const long *idx, json_t **out, struct err *e)
{
    const struct study_source *base = idx ? &s->base : &s->preps[prep].base;
    json_t *doc = json_deep_copy(base->doc);
    if (!doc)
        return err_nomem(e, "case");
    int rc = 0;
    if (!idx) {
        const struct study_prep *p = &s->preps[prep];
        for (int i = 0; i < p->nset && !rc; i++)
            rc = apply(s, doc, p->set[i].path, p->set[i].value, p->set[i].where, e);
    } else {
        for (int i = 0; i < s->nset && !rc; i++)
            rc = apply(s, doc, s->set[i].path, s->set[i].value, s->set[i].where, e);
        for (int a = 0; a < s->naxes && !rc; a++) {
            const struct study_axis *ax = &s->axes[a];
            rc = apply(s, doc, ax->path, json_array_get(ax->values, (size_t)idx[ax->group]),
                       ax->where, e);
        }
    }
    if (rc) {
        json_decref(doc);
        return rc;
    }
    *out = doc;
    return 0;
}

json_t *study_job_params(const struct study *s, const long *idx)
{
    json_t *p = json_object();
    for (int a = 0; a < s->naxes; a++) {
        const struct study_axis *ax = &s->axes[a];
        json_object_set(p, ax->path, json_array_get(ax->values, (size_t)idx[ax->group]));
    }
    return p;
}
