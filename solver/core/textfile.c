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
    t->fp = fopen(path, "r");
    if (!t->fp)
        return err_set(e, ERR_INPUT, "%s: cannot open: %s", path, strerror(errno));
    t->cursor = t->buf;
    return 0;
}

void textfile_close(struct textfile *t)
{
    if (t->fp)
        fclose(t->fp);
    t->fp = NULL;
}

int textfile_next_line(struct textfile *t)
{
    if (!t->fp || !fgets(t->buf, sizeof t->buf, t->fp)) {
        t->eof = 1;
        t->buf[0] = '\0';
        t->cursor = t->buf;
        return -1;
    }
    t->line++;
    size_t len = strlen(t->buf);
    /* a line longer than the buffer: the rest is read as the next "line" */
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

int textfile_error(struct textfile *t, struct err *e, const char *fmt, ...)
{
    char what[ERR_MSG_MAX / 2];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return err_set(e, ERR_INPUT, "%s:%d: %s", t->path, t->line, what);
}

int text_parse_real(const char *tok, double *out)
{
    /* strtod also takes hex floats, "inf" and "nan": a data file holds none */
    if (!tok || !*tok || strpbrk(tok, "xXpP"))
        return -1;
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (*end || end == tok || !isfinite(v) || errno == ERANGE)
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

int textfile_double(struct textfile *t, double *out, const char *what, struct err *e)
{
    const char *tok = textfile_token(t);
    if (!tok)
        return textfile_error(t, e, "unexpected end of file while reading %s", what);
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    /* Fortran-style exponents (1.0D-03) appear in old DYNAMO files */
    if (*end == 'D' || *end == 'd') {
        char tmp[64];
        snprintf(tmp, sizeof tmp, "%s", tok);
        char *dpos = tmp + (end - tok);
        *dpos = 'e';
        v = strtod(tmp, &end);
        end = (char *)tok + (end - tmp);
    }
    if (*end || end == tok || !isfinite(v))
        return textfile_error(t, e, "expected a number for %s, found '%s'", what, tok);
    *out = v;
    return 0;
}

int textfile_doubles(struct textfile *t, double *out, long n, const char *what, struct err *e)
{
    for (long i = 0; i < n; i++) {
        const char *tok = textfile_token(t);
        if (!tok)
            return textfile_error(t, e, "unexpected end of file: %s needs %ld values, found %ld",
                                  what, n, i);
        char *end;
        double v = strtod(tok, &end);
        if (*end || end == tok || !isfinite(v))
            return textfile_error(t, e, "expected a number (value %ld of %s), found '%s'", i + 1,
                                  what, tok);
        out[i] = v;
    }
    return 0;
}

int textfile_int(struct textfile *t, long *out, const char *what, struct err *e)
{
    const char *tok = textfile_token(t);
    if (!tok)
        return textfile_error(t, e, "unexpected end of file while reading %s", what);
    char *end;
    errno = 0;
    long v = strtol(tok, &end, 10);
    if (*end || end == tok || errno)
        return textfile_error(t, e, "expected an integer for %s, found '%s'", what, tok);
    *out = v;
    return 0;
}
