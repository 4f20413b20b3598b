/* textfile: line-aware tokenizer used by file readers. */
#include "core/textfile.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int textfile_open(struct textfile *t, const char *path, struct err *e)
{
    memset(t, 0, sizeof *t);
    snprintf(t->path, sizeof t->path, "%s", path);
    t->cap = 256;
    t->buf = calloc(t->cap, 1);
    if (!t->buf)
        return err_nomem(e, "line buffer");
    t->fp = fopen(path, "r");
    if (!t->fp) {
        int code = err_set(e, ERR_INPUT, "%s: cannot open: %s", path, strerror(errno));
        free(t->buf);
        t->buf = NULL;
        return code;
    }
    t->cursor = t->buf;
    return 0;
}

void textfile_close(struct textfile *t)
{
    if (t->fp)
        fclose(t->fp);
    t->fp = NULL;
    free(t->buf);
    t->buf = t->cursor = NULL;
    t->cap = 0;
}

int textfile_next_line(struct textfile *t)
{
    /* getline, not a fixed buffer: a long line cut in two would be read
     * as two lines, its tokens split and the line numbers shifted */
    ssize_t len = t->fp ? getline(&t->buf, &t->cap, t->fp) : -1;
    if (len < 0) {
        t->eof = 1;
        if (t->buf)
            t->buf[0] = '\0';
        t->cursor = t->buf;
        return -1;
    }
    t->line++;
    /* a NUL inside the line ends it for every reader alike */
    len = (ssize_t)strlen(t->buf);
    if (len > 0 && t->buf[len - 1] == '\n')
        t->buf[--len] = '\0';
    if (len > 0 && t->buf[len - 1] == '\r')
        t->buf[--len] = '\0';
    if (t->strip_comments) {
        char *hash = strchr(t->buf, '#');
        if (hash)
            *hash = '\0';
    }
    t->cursor = t->buf;
    return 0;
}

int textfile_next_content_line(struct textfile *t)
{
    while (textfile_next_line(t) == 0) {
        const char *s = t->buf + strspn(t->buf, " \t");
        if (*s && *s != '#')
            return 0;
    }
    return -1;
}

const char *textfile_token(struct textfile *t)
{
    for (;;) {
        char *s = t->cursor + strspn(t->cursor, " \t\r\n\f");
        if (*s) {
            char *end = s + strcspn(s, " \t\r\n\f");
            if (*end)
                *end++ = '\0';
            t->cursor = end;
            return s;
        }
        if (textfile_next_line(t) != 0)
            return NULL;
    }
}

const char *text_excerpt(const char *s, char out[TEXT_EXCERPT_SIZE])
{
    size_t n = strlen(s), keep = n;
    if (n > TEXT_EXCERPT_MAX) {
        keep = TEXT_EXCERPT_MAX;
        /* do not cut a UTF-8 sequence in two */
        while (keep > 0 && ((unsigned char)s[keep] & 0xC0) == 0x80)
            keep--;
    }
    for (size_t i = 0; i < keep; i++) {
        unsigned char c = (unsigned char)s[i];
        out[i] = c < 0x20 || c == 0x7f ? '?' : (char)c;
    }
    if (keep < n) {
        memcpy(out + keep, "...", 4);
    } else {
        out[keep] = '\0';
    }
    return out;
}

static int vtextfile_error(struct textfile *t, int line, struct err *e, const char *fmt,
                           va_list ap)
{
    char what[ERR_MSG_MAX / 2];
    vsnprintf(what, sizeof what, fmt, ap);
    return err_set(e, ERR_INPUT, "%s:%d: %s", t->path, line, what);
}

int textfile_error(struct textfile *t, struct err *e, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = vtextfile_error(t, t->line, e, fmt, ap);
    va_end(ap);
    return rc;
}

int textfile_error_at(struct textfile *t, int line, struct err *e, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = vtextfile_error(t, line, e, fmt, ap);
    va_end(ap);
    return rc;
}

int text_parse_real(const char *tok, double *out)
{
    /* strtod also takes hex floats, "inf" and "nan": a data file holds none */
    if (!tok || !*tok || strpbrk(tok, "xXpP"))
        return -1;
    char *end;
    double v = strtod(tok, &end);
    /* overflow gives +-HUGE_VAL (not finite, refused); an underflow to 0 or
     * a denormal is the number the file means, near enough */
    if (*end || end == tok || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int text_parse_long(const char *tok, long *out)
{
    if (!tok || !*tok)
        return -1;
    char *end;
    errno = 0;
    long v = strtol(tok, &end, 10);
    if (*end || end == tok || errno)
        return -1;
    *out = v;
    return 0;
}

/* text_parse_real, also with a Fortran exponent letter (1.0D-03). */
static int parse_real_fortran(const char *tok, double *out)
{
    const char *dpos = strpbrk(tok, "dD");
    if (!dpos)
        return text_parse_real(tok, out);
    char tmp[64];
    size_t len = strlen(tok);
    if (len >= sizeof tmp || strpbrk(dpos + 1, "dD"))
        return -1;
    memcpy(tmp, tok, len + 1);
    tmp[dpos - tok] = 'e';
    return text_parse_real(tmp, out);
}

int textfile_double(struct textfile *t, double *out, const char *what, struct err *e)
{
    return textfile_doubles(t, out, 1, what, e);
}

int textfile_doubles(struct textfile *t, double *out, long n, const char *what, struct err *e)
{
    for (long i = 0; i < n; i++) {
        const char *tok = textfile_token(t);
        if (!tok) {
            if (n == 1)
                return textfile_error(t, e, "unexpected end of file while reading %s", what);
            return textfile_error(t, e, "unexpected end of file: %s needs %ld values, found %ld",
                                  what, n, i);
        }
        if (parse_real_fortran(tok, &out[i]) != 0) {
            char ex[TEXT_EXCERPT_SIZE];
            if (n == 1)
                return textfile_error(t, e, "expected a number for %s, found '%s'", what,
                                      text_excerpt(tok, ex));
            return textfile_error(t, e, "expected a number (value %ld of %s), found '%s'", i + 1,
                                  what, text_excerpt(tok, ex));
        }
    }
    return 0;
}

int textfile_int(struct textfile *t, long *out, const char *what, struct err *e)
{
    const char *tok = textfile_token(t);
    if (!tok)
        return textfile_error(t, e, "unexpected end of file while reading %s", what);
    if (text_parse_long(tok, out) != 0) {
        char ex[TEXT_EXCERPT_SIZE];
        return textfile_error(t, e, "expected an integer for %s, found '%s'", what,
                              text_excerpt(tok, ex));
    }
    return 0;
}
