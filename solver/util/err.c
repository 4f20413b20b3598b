/* err: implementation of the error convention described in err.h. */
#include "util/err.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static int set_message(struct err *e, int code, int elsewhere, const char *fmt, va_list ap)
{
    if (e) {
        vsnprintf(e->msg, sizeof e->msg, fmt, ap);
        e->code = code;
        e->elsewhere = elsewhere;
    }
    return code;
}

int err_set(struct err *e, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    set_message(e, code, 0, fmt, ap);
    va_end(ap);
    return code;
}

int err_set_elsewhere(struct err *e, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    set_message(e, code, 1, fmt, ap);
    va_end(ap);
    return code;
}

int err_prefix(struct err *e, const char *fmt, ...)
{
    if (!e)
        return ERR_RUNTIME;
    char head[ERR_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(head, sizeof head, fmt, ap);
    va_end(ap);
    char tmp[ERR_MSG_MAX];
    snprintf(tmp, sizeof tmp, "%s%s", head, e->msg);
    memcpy(e->msg, tmp, sizeof e->msg);
    return e->code;
}

int err_nomem(struct err *e, const char *what)
{
    return err_set(e, ERR_RUNTIME, "out of memory (%s)", what);
}

void err_clear(struct err *e)
{
    if (e) {
        e->code = ERR_OK;
        e->elsewhere = 0;
        e->msg[0] = '\0';
    }
}
