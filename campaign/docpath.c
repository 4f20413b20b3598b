/* docpath: dotted key paths into case documents; ${prep.NAME} references. */
#include "docpath.h"

#include <stdlib.h>
#include <string.h>
#include "util/mem.h"

int docpath_valid(const char *path)
{
    if (!path || !*path || strlen(path) >= DOCPATH_MAX)
        return 0;
    int prev_dot = 1;
    for (const char *c = path; *c; c++) {
        if (*c == '.') {
            if (prev_dot)
                return 0;
            prev_dot = 1;
            continue;
        }
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
              *c == '_' || *c == '-'))
            return 0;
        prev_dot = 0;
    }
    return !prev_dot;
}

json_t *docpath_get(json_t *doc, const char *path)
{
    char buf[DOCPATH_MAX];
    snprintf(buf, sizeof buf, "%s", path);
    json_t *node = doc;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ".", &save); tok; tok = strtok_r(NULL, ".", &save)) {
        if (!json_is_object(node))
            return NULL;
        node = json_object_get(node, tok);
        if (!node)
            return NULL;
    }
    return node;
}

int docpath_set(json_t *doc, const char *path, json_t *value, char *bad, size_t badlen)
{
    char buf[DOCPATH_MAX];
    snprintf(buf, sizeof buf, "%s", path);
    json_t *node = doc;
    char *save = NULL;
    char *tok = strtok_r(buf, ".", &save);
    while (tok) {
        char *next = strtok_r(NULL, ".", &save);
        if (!next) {
            if (json_is_null(value)) {
                json_object_del(node, tok);
                json_decref(value);
            } else {
                json_object_set_new(node, tok, value);
            }
            return 0;
        }
        json_t *child = json_object_get(node, tok);
        if (!child || json_is_null(child)) {
            if (json_is_null(value)) {   /* deleting under an absent key: nothing to do */
                json_decref(value);
                return 0;
            }
            child = json_object();
            json_object_set_new(node, tok, child);
        } else if (!json_is_object(child)) {
            if (bad) {
                size_t len = (size_t)(tok - buf) + strlen(tok);
                snprintf(bad, badlen, "%.*s", (int)len, path);
            }
            json_decref(value);
            return -1;
        }
        node = child;
        tok = next;
    }
    json_decref(value);
    return -1;
}

int docpath_under(const char *a, const char *b)
{
    size_t lb = strlen(b);
    return strncmp(a, b, lb) == 0 && (a[lb] == '\0' || a[lb] == '.');
}

int docpath_overlap(const char *a, const char *b)
{
    return docpath_under(a, b) || docpath_under(b, a);
}

/* --- references ----------------------------------------------------------- */

/* Parse a reference at s (which starts with "${").  Sets name (NUL-ended in
 * out), whether it is the key form, and returns its length, or 0. */
static size_t parse_ref(const char *s, char *out, size_t outlen, int *is_key)
{
    const char *p;
    if (strncmp(s, "${prep.", 7) == 0) {
        *is_key = 0;
        p = s + 7;
    } else if (strncmp(s, "${prep:", 7) == 0) {
        *is_key = 1;
        p = s + 7;
    } else {
        return 0;
    }
    const char *q = p;
    while ((*q >= 'a' && *q <= 'z') || (*q >= 'A' && *q <= 'Z') || (*q >= '0' && *q <= '9') ||
           *q == '_' || *q == '-')
        q++;
    if (q == p || *q != '}' || (size_t)(q - p) >= outlen)
        return 0;
    memcpy(out, p, (size_t)(q - p));
    out[q - p] = '\0';
    return (size_t)(q - s) + 1;
}

int docpath_has_bad_ref(const char *s)
{
    for (const char *c = strstr(s, "${"); c; c = strstr(c + 2, "${")) {
        char name[128];
        int k;
        if (!parse_ref(c, name, sizeof name, &k))
            return 1;
    }
    return 0;
}

static int visit(const json_t *v, char *path, size_t len, docpath_ref_fn fn, void *ctx)
{
    if (json_is_string(v)) {
        const char *s = json_string_value(v);
        for (const char *c = strstr(s, "${"); c; c = strstr(c + 2, "${")) {
            char name[128];
            int k;
            if (parse_ref(c, name, sizeof name, &k) && !k) {
                int rc = fn(ctx, path, name);
                if (rc)
                    return rc;
            }
        }
        return 0;
    }
    size_t base = strlen(path);
    if (json_is_object(v)) {
        const char *key;
        json_t *x;
        json_object_foreach((json_t *)v, key, x)
        {
            snprintf(path + base, len - base, "%s%s", base ? "." : "", key);
            int rc = visit(x, path, len, fn, ctx);
            path[base] = '\0';
            if (rc)
                return rc;
        }
    } else if (json_is_array(v)) {
        size_t i;
        json_t *x;
        json_array_foreach(v, i, x)
        {
            snprintf(path + base, len - base, "[%zu]", i);
            int rc = visit(x, path, len, fn, ctx);
            path[base] = '\0';
            if (rc)
                return rc;
        }
    }
    return 0;
}

int docpath_refs_visit(const json_t *doc, docpath_ref_fn fn, void *ctx)
{
    char path[1024] = "";
    return visit(doc, path, sizeof path, fn, ctx);
}

static int replace_in_string(json_t *str, docpath_subst_fn subst, void *ctx)
{
    const char *s = json_string_value(str);
    if (!strstr(s, "${"))
        return 0;
    size_t cap = strlen(s) + 256, len = 0;
    char *out = mem_alloc(cap);
    if (!out)
        return -1;
    const char *c = s;
    while (*c) {
        char name[128];
        int is_key;
        size_t n = c[0] == '$' ? parse_ref(c, name, sizeof name, &is_key) : 0;
        const char *piece = c;
        size_t plen = 1;
        if (n) {
            piece = subst(ctx, name, is_key);
            if (!piece) {
                free(out);
                return -1;
            }
            plen = strlen(piece);
        }
        if (len + plen + 1 > cap) {
            cap = 2 * (len + plen + 1);
            char *grown = mem_realloc(out, cap);
            if (!grown) {
                free(out);
                return -1;
            }
            out = grown;
        }
        memcpy(out + len, piece, plen);
        len += plen;
        c += n ? n : 1;
    }
    out[len] = '\0';
    json_string_set(str, out);
    free(out);
    return 0;
}

int docpath_refs_replace(json_t *doc, docpath_subst_fn subst, void *ctx)
{
    if (json_is_string(doc))
        return replace_in_string(doc, subst, ctx);
    if (json_is_object(doc)) {
        const char *key;
        json_t *x;
        json_object_foreach(doc, key, x) if (docpath_refs_replace(x, subst, ctx) != 0) return -1;
    } else if (json_is_array(doc)) {
        size_t i;
        json_t *x;
        json_array_foreach(doc, i, x) if (docpath_refs_replace(x, subst, ctx) != 0) return -1;
    }
    return 0;
}
