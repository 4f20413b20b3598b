/* yamldoc: libyaml event stream -> jansson tree + location map. */
#include "util/yamldoc.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "util/canon.h"
#include "util/mem.h"

#define PATH_MAX_LEN 512
#define MAX_ANCHORS 256
#define MAX_DEPTH 64

struct anchor {
    char *name;
    json_t *value;
};

struct ydoc_parser {
    yaml_parser_t yp;
    const char *name;
    struct locmap *locs;
    struct err *e;
    struct anchor anchors[MAX_ANCHORS];
    int nanchors;
};

static int fail_at(struct ydoc_parser *p, yaml_mark_t m, const char *fmt, const char *arg)
{
    char what[ERR_MSG_MAX / 2];
    snprintf(what, sizeof what, fmt, arg ? arg : "");
    return err_set(p->e, ERR_INPUT, "%s:%zu:%zu: %s", p->name, m.line + 1, m.column + 1, what);
}

static int next_event(struct ydoc_parser *p, yaml_event_t *ev)
{
    if (!yaml_parser_parse(&p->yp, ev)) {
        yaml_mark_t m = p->yp.problem_mark;
        return err_set(p->e, ERR_INPUT, "%s:%zu:%zu: YAML syntax error: %s%s%s", p->name,
                       m.line + 1, m.column + 1, p->yp.problem ? p->yp.problem : "unknown",
                       p->yp.context ? " " : "", p->yp.context ? p->yp.context : "");
    }
    return 0;
}

/* Convert a plain scalar by the YAML 1.2 core schema. */
static json_t *plain_scalar(const char *s, size_t len)
{
    if (len == 0 || strcmp(s, "~") == 0 || strcmp(s, "null") == 0 || strcmp(s, "Null") == 0 ||
        strcmp(s, "NULL") == 0)
        return json_null();
    if (strcmp(s, "true") == 0 || strcmp(s, "True") == 0 || strcmp(s, "TRUE") == 0)
        return json_true();
    if (strcmp(s, "false") == 0 || strcmp(s, "False") == 0 || strcmp(s, "FALSE") == 0)
        return json_false();
    /* integer: [-+]?[0-9]+ */
    size_t i = (s[0] == '-' || s[0] == '+') ? 1 : 0;
    int all_digits = i < len;
    for (size_t k = i; k < len; k++)
        if (s[k] < '0' || s[k] > '9')
            all_digits = 0;
    if (all_digits) {
        errno = 0;
        char *end;
        long long v = strtoll(s, &end, 10);
        if (errno == 0 && *end == '\0')
            return json_integer(v);
    }
    /* real: anything strtod consumes entirely, except nan/inf spellings */
    int has_digit = 0;
    for (size_t k = 0; k < len; k++)
        if (s[k] >= '0' && s[k] <= '9')
            has_digit = 1;
    if (has_digit) {
        errno = 0;
        char *end;
        double v = strtod(s, &end);
        if (*end == '\0' && isfinite(v) && errno != ERANGE)
            return json_real(v);
    }
    return json_stringn(s, len);
}

static int record(struct ydoc_parser *p, const char *path, const yaml_mark_t *key, yaml_mark_t val)
{
    struct loc l = {0, 0, (int)val.line + 1, (int)val.column + 1};
    if (key) {
        l.key_line = (int)key->line + 1;
        l.key_col = (int)key->column + 1;
    }
    if (p->locs && locmap_put(p->locs, path, l) != 0)
        return err_set(p->e, ERR_RUNTIME, "%s: out of memory (location map)", p->name);
    return 0;
}

static int parse_node(struct ydoc_parser *p, yaml_event_t *ev, const char *path,
                      const yaml_mark_t *keymark, int depth, json_t **out);

static int add_anchor(struct ydoc_parser *p, const yaml_char_t *anchor, json_t *v, yaml_mark_t m)
{
    if (!anchor)
        return 0;
    if (p->nanchors >= MAX_ANCHORS)
        return fail_at(p, m, "too many YAML anchors%s", NULL);
    p->anchors[p->nanchors].name = mem_strdup((const char *)anchor);
    p->anchors[p->nanchors].value = json_incref(v);
    p->nanchors++;
    return 0;
}

static int parse_mapping(struct ydoc_parser *p, const char *path, int depth, json_t **out)
{
    json_t *obj = json_object();
    yaml_event_t ev;
    for (;;) {
        int rc = next_event(p, &ev);
        if (rc) {
            json_decref(obj);
            return rc;
        }
        if (ev.type == YAML_MAPPING_END_EVENT) {
            yaml_event_delete(&ev);
            break;
        }
        if (ev.type != YAML_SCALAR_EVENT) {
            rc = fail_at(p, ev.start_mark, "mapping keys must be plain scalars%s", NULL);
            yaml_event_delete(&ev);
            json_decref(obj);
            return rc;
        }
        char key[256];
        snprintf(key, sizeof key, "%s", (const char *)ev.data.scalar.value);
        yaml_mark_t keymark = ev.start_mark;
        yaml_event_delete(&ev);
        if (strcmp(key, "<<") == 0) {
            json_decref(obj);
            return fail_at(p, keymark, "YAML merge keys ('<<') are not supported%s", NULL);
        }
        if (json_object_get(obj, key)) {
            json_decref(obj);
            return fail_at(p, keymark, "duplicate key '%s'", key);
        }
        char child[PATH_MAX_LEN];
        snprintf(child, sizeof child, "%s%s%s", path, path[0] ? "." : "", key);
        if ((rc = next_event(p, &ev))) {
            json_decref(obj);
            return rc;
        }
        json_t *v = NULL;
        rc = parse_node(p, &ev, child, &keymark, depth + 1, &v);
        if (rc) {
            json_decref(obj);
            return rc;
        }
        json_object_set_new(obj, key, v);
    }
    *out = obj;
    return 0;
}

static int parse_sequence(struct ydoc_parser *p, const char *path, int depth, json_t **out)
{
    json_t *arr = json_array();
    yaml_event_t ev;
    for (size_t i = 0;; i++) {
        int rc = next_event(p, &ev);
        if (rc) {
            json_decref(arr);
            return rc;
        }
        if (ev.type == YAML_SEQUENCE_END_EVENT) {
            yaml_event_delete(&ev);
            break;
        }
        char child[PATH_MAX_LEN];
        snprintf(child, sizeof child, "%s[%zu]", path, i);
        json_t *v = NULL;
        rc = parse_node(p, &ev, child, NULL, depth + 1, &v);
        if (rc) {
            json_decref(arr);
            return rc;
        }
        json_array_append_new(arr, v);
    }
    *out = arr;
    return 0;
}

/* Consumes *ev (deletes it). */
static int parse_node(struct ydoc_parser *p, yaml_event_t *ev, const char *path,
                      const yaml_mark_t *keymark, int depth, json_t **out)
{
    yaml_mark_t m = ev->start_mark;
    int rc = 0;
    if (depth > MAX_DEPTH) {
        yaml_event_delete(ev);
        return fail_at(p, m, "document nested too deeply%s", NULL);
    }
    if (record(p, path, keymark, m) != 0) {
        yaml_event_delete(ev);
        return ERR_RUNTIME;
    }
    switch (ev->type) {
    case YAML_SCALAR_EVENT: {
        const char *s = (const char *)ev->data.scalar.value;
        size_t len = ev->data.scalar.length;
        int quoted = ev->data.scalar.style == YAML_SINGLE_QUOTED_SCALAR_STYLE ||
                     ev->data.scalar.style == YAML_DOUBLE_QUOTED_SCALAR_STYLE ||
                     ev->data.scalar.style == YAML_LITERAL_SCALAR_STYLE ||
                     ev->data.scalar.style == YAML_FOLDED_SCALAR_STYLE;
        *out = quoted ? json_stringn(s, len) : plain_scalar(s, len);
        if (!*out)
            rc = fail_at(p, m, "scalar is not valid UTF-8%s", NULL);
        else
            rc = add_anchor(p, ev->data.scalar.anchor, *out, m);
        yaml_event_delete(ev);
        return rc;
    }
    case YAML_MAPPING_START_EVENT: {
        yaml_char_t *anchor = ev->data.mapping_start.anchor
                                  ? (yaml_char_t *)mem_strdup((char *)ev->data.mapping_start.anchor)
                                  : NULL;
        yaml_event_delete(ev);
        rc = parse_mapping(p, path, depth, out);
        if (!rc)
            rc = add_anchor(p, anchor, *out, m);
        free(anchor);
        return rc;
    }
    case YAML_SEQUENCE_START_EVENT: {
        yaml_char_t *anchor = ev->data.sequence_start.anchor
                                  ? (yaml_char_t *)mem_strdup((char *)ev->data.sequence_start.anchor)
                                  : NULL;
        yaml_event_delete(ev);
        rc = parse_sequence(p, path, depth, out);
        if (!rc)
            rc = add_anchor(p, anchor, *out, m);
        free(anchor);
        return rc;
    }
    case YAML_ALIAS_EVENT: {
        const char *name = (const char *)ev->data.alias.anchor;
        for (int i = p->nanchors - 1; i >= 0; i--) {
            if (strcmp(p->anchors[i].name, name) == 0) {
                *out = json_deep_copy(p->anchors[i].value);
                yaml_event_delete(ev);
                return 0;
            }
        }
        rc = fail_at(p, m, "unknown YAML alias '*%s'", name);
        yaml_event_delete(ev);
        return rc;
    }
    default:
        yaml_event_delete(ev);
        return fail_at(p, m, "unexpected YAML structure%s", NULL);
    }
}

static int parse_stream(struct ydoc_parser *p, json_t **doc)
{
    yaml_event_t ev;
    int rc;
    json_t *root = NULL;
    int ndocs = 0;
    for (;;) {
        if ((rc = next_event(p, &ev)))
            goto fail;
        yaml_event_type_t t = ev.type;
        yaml_mark_t m = ev.start_mark;
        if (t == YAML_STREAM_END_EVENT) {
            yaml_event_delete(&ev);
            break;
        }
        if (t == YAML_DOCUMENT_START_EVENT) {
            yaml_event_delete(&ev);
            if (++ndocs > 1) {
                rc = fail_at(p, m, "a case file holds one YAML document, found a second%s", NULL);
                goto fail;
            }
            if ((rc = next_event(p, &ev)))
                goto fail;
            if ((rc = parse_node(p, &ev, "", NULL, 0, &root)))
                goto fail;
            continue;
        }
        yaml_event_delete(&ev);   /* stream start, document end */
    }
    if (!root)
        root = json_object();  /* an empty file is an empty mapping */
    *doc = root;
    return 0;
fail:
    json_decref(root);
    return rc;
}

int yamldoc_load_string(const char *text, size_t len, const char *name, json_t **doc,
                        struct locmap **locs, struct err *e)
{
    struct ydoc_parser p = {.name = name, .e = e};
    p.locs = locmap_create();
    if (!p.locs)
        return err_nomem(e, "location map");
    yaml_parser_initialize(&p.yp);
    yaml_parser_set_input_string(&p.yp, (const unsigned char *)text, len);
    json_t *root = NULL;
    int rc = parse_stream(&p, &root);
    yaml_parser_delete(&p.yp);
    for (int i = 0; i < p.nanchors; i++) {
        free(p.anchors[i].name);
        json_decref(p.anchors[i].value);
    }
    if (rc) {
        locmap_destroy(&p.locs);
        return rc;
    }
    *doc = root;
    *locs = p.locs;
    return 0;
}

int yamldoc_load_file(const char *path, json_t **doc, struct locmap **locs, struct err *e)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(e, ERR_INPUT, "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 8192, len = 0;
    char *buf = mem_alloc(cap);
    if (!buf) {
        fclose(f);
        return err_nomem(e, "file buffer");
    }
    size_t got;
    while ((got = fread(buf + len, 1, cap - len, f)) > 0) {
        len += got;
        if (len == cap) {
            char *nb = mem_realloc(buf, cap *= 2);
            if (!nb) {
                free(buf);
                fclose(f);
                return err_nomem(e, "file buffer");
            }
            buf = nb;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return err_set(e, ERR_INPUT, "%s: read error", path);
    }
    int rc = yamldoc_load_string(buf, len, path, doc, locs, e);
    free(buf);
    return rc;
}

/* --- writer --------------------------------------------------------------- */

static int needs_quotes(const char *s)
{
    if (!*s)
        return 1;
    json_t *probe = plain_scalar(s, strlen(s));
    int not_string = !json_is_string(probe);
    json_decref(probe);
    if (not_string)
        return 1;
    if (strpbrk(s, ":#{}[],&*!|>'\"%@`\n\t") || s[0] == ' ' || s[strlen(s) - 1] == ' ' ||
        s[0] == '-' || s[0] == '?')
        return 1;
    return 0;
}

static void write_scalar(FILE *out, const json_t *v)
{
    char buf[64];
    switch (json_typeof(v)) {
    case JSON_NULL: fputs("null", out); break;
    case JSON_TRUE: fputs("true", out); break;
    case JSON_FALSE: fputs("false", out); break;
    case JSON_INTEGER: fprintf(out, "%" JSON_INTEGER_FORMAT, json_integer_value(v)); break;
    case JSON_REAL:
        canon_real(json_real_value(v), buf, sizeof buf);
        fputs(buf, out);
        break;
    case JSON_STRING: {
        const char *s = json_string_value(v);
        if (!needs_quotes(s)) {
            fputs(s, out);
        } else {
            fputc('"', out);
            for (; *s; s++) {
                if (*s == '"' || *s == '\\')
                    fprintf(out, "\\%c", *s);
                else if (*s == '\n')
                    fputs("\\n", out);
                else if (*s == '\t')
                    fputs("\\t", out);
                else
                    fputc(*s, out);
            }
            fputc('"', out);
        }
        break;
    }
    default: break;
    }
}

static int is_flow_array(const json_t *v)
{
    size_t i;
    json_t *x;
    json_array_foreach(v, i, x) if (json_is_object(x) || json_is_array(x)) return 0;
    return 1;
}

static int cmp_keys(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* The writers return 0, or -1 when out of memory (the output is then
 * incomplete). */
static int write_node(FILE *out, const json_t *v, int indent);

static int write_object(FILE *out, const json_t *obj, int indent)
{
    size_t n = json_object_size(obj), k = 0;
    const char **keys = mem_alloc((n ? n : 1) * sizeof *keys);
    if (!keys)
        return -1;
    const char *key;
    json_t *val;
    json_object_foreach((json_t *)obj, key, val) keys[k++] = key;
    qsort(keys, n, sizeof *keys, cmp_keys);
    int rc = 0;
    for (size_t i = 0; i < n && !rc; i++) {
        val = json_object_get(obj, keys[i]);
        fprintf(out, "%*s%s:", indent, "", keys[i]);
        if (json_is_object(val) && json_object_size(val) > 0) {
            fputc('\n', out);
            rc = write_object(out, val, indent + 2);
        } else if (json_is_array(val) && !is_flow_array(val)) {
            fputc('\n', out);
            rc = write_node(out, val, indent + 2);
        } else {
            fputc(' ', out);
            rc = write_node(out, val, indent + 2);
            fputc('\n', out);
        }
    }
    free(keys);
    return rc;
}

static int write_node(FILE *out, const json_t *v, int indent)
{
    int rc = 0;
    if (json_is_object(v)) {
        if (json_object_size(v) == 0)
            fputs("{}", out);
        else
            rc = write_object(out, v, indent);
    } else if (json_is_array(v)) {
        size_t i;
        json_t *x;
        if (is_flow_array(v)) {
            fputc('[', out);
            json_array_foreach(v, i, x)
            {
                if (i)
                    fputs(", ", out);
                write_scalar(out, x);
            }
            fputc(']', out);
        } else {
            json_array_foreach(v, i, x)
            {
                if (rc)
                    break;
                fprintf(out, "%*s-", indent, "");
                if (json_is_object(x) && json_object_size(x) > 0) {
                    /* first key on the dash line, the rest indented */
                    fputc('\n', out);
                    rc = write_object(out, x, indent + 2);
                } else {
                    fputc(' ', out);
                    rc = write_node(out, x, indent + 2);
                    fputc('\n', out);
                }
            }
        }
    } else {
        write_scalar(out, v);
    }
    return rc;
}

int yamldoc_write(FILE *out, const json_t *doc)
{
    int rc;
    if (json_is_object(doc)) {
        rc = write_object(out, doc, 0);
    } else {
        rc = write_node(out, doc, 0);
        fputc('\n', out);
    }
    if (rc)
        return -1;
    return ferror(out) ? -1 : 0;
}
