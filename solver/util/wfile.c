/* wfile: temporary file, fsync, rename (wfile.h). */
#include "util/wfile.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/fault.h"

int wfile_open(struct wfile *w, const char *path, struct err *e)
{
    w->f = NULL;
    w->no_sync = 0;
    snprintf(w->path, sizeof w->path, "%s", path);
    if (snprintf(w->tmp, sizeof w->tmp, "%s.tmp", path) >= (int)sizeof w->tmp)
        return err_set(e, ERR_RUNTIME, "cannot write %s: the name is too long", path);
    if (fault_write(ENOSPC) != 0 || !(w->f = fopen(w->tmp, "w"))) {
        int err = errno;
        err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(err));
        errno = err;   /* for callers that tell a bad path from a full disk */
        return ERR_RUNTIME;
    }
    return 0;
}

/* Close and remove the temporary file, with the error of `what` in e. */
static int fail(struct wfile *w, struct err *e)
{
    int err = errno;
    wfile_discard(w);
    return err_set(e, ERR_RUNTIME, "cannot write %s: %s", w->path,
                   strerror(err ? err : EIO));
}

int wfile_flush(struct wfile *w, struct err *e)
{
    if (!w->f)
        return err_set(e, ERR_RUNTIME, "cannot write %s: not open", w->path);
    errno = 0;
    if (fault_write(ENOSPC) != 0 || fflush(w->f) != 0 || ferror(w->f))
        return fail(w, e);
    return 0;
}

int wfile_commit(struct wfile *w, struct err *e)
{
    if (!w->f)
        return 0;
    errno = 0;
    if (fault_write(ENOSPC) != 0 || fflush(w->f) != 0 || ferror(w->f))
        return fail(w, e);
    if (!w->no_sync && (fault_write(EIO) != 0 || fsync(fileno(w->f)) != 0))
        return fail(w, e);
    FILE *f = w->f;
    w->f = NULL;
    if (fclose(f) != 0) {
        int err = errno;
        unlink(w->tmp);
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", w->path, strerror(err));
    }
    if (wfile_rename(w->tmp, w->path) != 0) {
        int err = errno;
        unlink(w->tmp);
        return err_set(e, ERR_RUNTIME, "cannot write %s: rename from %s: %s", w->path, w->tmp,
                       strerror(err));
    }
    return 0;
}

void wfile_discard(struct wfile *w)
{
    if (!w->f)
        return;
    fclose(w->f);
    w->f = NULL;
    unlink(w->tmp);
}

int wfile_write_text(const char *path, const char *text, int durable, struct err *e)
{
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    w.no_sync = !durable;
    fputs(text, w.f);
    return wfile_commit(&w, e);
}

int wfile_mkdir(const char *path, unsigned mode)
{
    /* a directory that exists already takes no write: no fault point there,
     * so an injected fault never claims an existing /tmp could not be made */
    struct stat sb;
    if (fault_installed() && stat(path, &sb) != 0 && fault_write(ENOSPC) != 0)
        return -1;
    return mkdir(path, (mode_t)mode);
}

int wfile_rename(const char *from, const char *to)
{
    if (fault_write(ENOSPC) != 0)
        return -1;
    return rename(from, to);
}
