/* canon: canonical JSON serialisation (see canon.h). */
#include "util/canon.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/mem.h"
#include "util/sha256.h"

struct sbuf {
    char *s;
    size_t len, cap;
    int oom;
    int fixed;   /* s is the caller's buffer of cap bytes: cut, never grown */
};

static void sb_put(struct sbuf *b, const char *s, size_t n)
{
    if (b->oom)
        return;
    if (b->fixed && b->len + n + 1 > b->cap)
        n = b->cap - 1 - b->len;
    if (b->len + n + 1 > b->cap) {
        size_t ncap = b->cap ? b->cap : 256;
        while (ncap < b->len + n + 1)
            ncap *= 2;
        char *ns = mem_realloc(b->s, ncap);
        if (!ns) {
            b->oom = 1;
            return;
        }
        b->s = ns;
        b->cap = ncap;
    }
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}

static void sb_puts(struct sbuf *b, const char *s) { sb_put(b, s, strlen(s)); }

void canon_real(double x, char *buf, size_t len)
{
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(buf, len, "%.*g", prec, x);
        if (strtod(buf, NULL) == x)
            break;
    }
    /* prefer plain decimals (600.0, not 6e+02) for ordinary magnitudes */
    double ax = x < 0 ? -x : x;
    if (strpbrk(buf, "eE") && ax >= 1e-4 && ax < 1e15) {
        char fixed[64];
        for (int dec = 1; dec <= 20; dec++) {
            snprintf(fixed, sizeof fixed, "%.*f", dec, x);
            if (strtod(fixed, NULL) == x) {
                snprintf(buf, len, "%s", fixed);
                break;
            }
        }
    }
    if (!strpbrk(buf, ".eEn") && strlen(buf) + 3 < len)
        strcat(buf, ".0");
}

static void put_string(struct sbuf *b, const char *s)
{
    sb_put(b, "\"", 1);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        char esc[8];
        if (c == '"' || c == '\\') {
            esc[0] = '\\';
            esc[1] = (char)c;
            sb_put(b, esc, 2);
        } else if (c < 0x20) {
            snprintf(esc, sizeof esc, "\\u%04x", c);
            sb_puts(b, esc);
        } else {
            sb_put(b, (const char *)&c, 1);
        }
    }
    sb_put(b, "\"", 1);
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static void put_value(struct sbuf *b, const json_t *v)
{
    char num[64];
    switch (json_typeof(v)) {
    case JSON_NULL: sb_puts(b, "null"); break;
    case JSON_TRUE: sb_puts(b, "true"); break;
    case JSON_FALSE: sb_puts(b, "false"); break;
    case JSON_INTEGER:
        snprintf(num, sizeof num, "%" JSON_INTEGER_FORMAT, json_integer_value(v));
        sb_puts(b, num);
        break;
    case JSON_REAL:
        canon_real(json_real_value(v), num, sizeof num);
        sb_puts(b, num);
        break;
    case JSON_STRING: put_string(b, json_string_value(v)); break;
    case JSON_ARRAY: {
        sb_put(b, "[", 1);
        for (size_t i = 0; i < json_array_size(v); i++) {
            if (i)
                sb_put(b, ",", 1);
            put_value(b, json_array_get(v, i));
        }
        sb_put(b, "]", 1);
        break;
    }
    case JSON_OBJECT: {
        size_t n = json_object_size(v), k = 0;
        const char **keys = mem_alloc((n ? n : 1) * sizeof *keys);
        if (!keys) {
            b->oom = 1;
            return;
        }
        const char *key;
        json_t *val;
        json_object_foreach((json_t *)v, key, val) keys[k++] = key;
        qsort(keys, n, sizeof *keys, cmp_str);
        sb_put(b, "{", 1);
        for (size_t i = 0; i < n; i++) {
            if (i)
                sb_put(b, ",", 1);
            put_string(b, keys[i]);
            sb_put(b, ":", 1);
            put_value(b, json_object_get(v, keys[i]));
        }
        sb_put(b, "}", 1);
        free(keys);
        break;
    }
    }
}

int canon_json_into(const json_t *v, char *buf, size_t len)
{
    if (len == 0)
        return 0;
    buf[0] = '\0';
    struct sbuf b = {buf, 0, len, 0, 1};
    put_value(&b, v);
    return b.oom ? -1 : 0;
}

char *canon_json(const json_t *v)
{
    struct sbuf b = {0};
    put_value(&b, v);
    if (b.oom) {
        free(b.s);
        return NULL;
    }
    return b.s;
}

int canon_key(const json_t *v, char key[CANON_KEY_LEN + 1])
{
    char *text = canon_json(v);
    if (!text) {
        key[0] = '\0';
        return -1;
    }
    char hex[65];
    sha256_hex(text, strlen(text), hex);
    free(text);
    memcpy(key, hex, CANON_KEY_LEN);
    key[CANON_KEY_LEN] = '\0';
    return 0;
}
