/* db_fault: failing the Nth SQLite write/sync or allocation (see db_fault.h). */
#include "db_fault.h"

#include <errno.h>
#include <sqlite3.h>
#include <stdlib.h>
#include <string.h>

/* --- the counters: the campaign library's one piece of global state ------- */

struct fault_hook {
    int on;          /* installed */
    long at;         /* fail call number `at` (1-based); 0: count only */
    int persist;     /* and every call after it */
    long calls;      /* calls seen */
    long failed;     /* calls failed */
};

static struct fault_hook io_hook, mem_hook;
static sqlite3_vfs *real_vfs;
static sqlite3_mem_methods real_mem;

/* Count a call; whether it is to fail. */
static int fault_hit(struct fault_hook *h)
{
    long n = ++h->calls;
    int hit = h->at > 0 && (n == h->at || (h->persist && n > h->at));
    if (hit)
        h->failed++;
    return hit;
}

static int parse_spec(const char *name, const char *spec, struct fault_hook *h, struct err *e)
{
    memset(h, 0, sizeof *h);
    if (!spec || !spec[0])
        return 0;
    char *end;
    errno = 0;
    long n = strtol(spec, &end, 10);
    if (end == spec || errno || n < 0 || (*end && strcmp(end, "+") != 0))
        return err_set(e, ERR_INPUT,
                       "%s=%s: expected N (fail the Nth call), N+ (fail it and every later one) "
                       "or 0 (count only)",
                       name, spec);
    h->on = 1;
    h->at = n;
    h->persist = *end == '+';
    return 0;
}

/* --- the I/O hook: a VFS over the default one -------------------------------- */

struct fault_file {
    sqlite3_file base;
    sqlite3_file *real;   /* follows this struct in the same allocation */
};

#define REAL(f) (((struct fault_file *)(f))->real)

static int f_close(sqlite3_file *f)
{
    int rc = REAL(f)->pMethods->xClose(REAL(f));
    f->pMethods = NULL;
    return rc;
}
static int f_read(sqlite3_file *f, void *buf, int amt, sqlite3_int64 off)
{
    return REAL(f)->pMethods->xRead(REAL(f), buf, amt, off);
}
static int f_write(sqlite3_file *f, const void *buf, int amt, sqlite3_int64 off)
{
    if (fault_hit(&io_hook))
        return SQLITE_FULL;
    return REAL(f)->pMethods->xWrite(REAL(f), buf, amt, off);
}
static int f_truncate(sqlite3_file *f, sqlite3_int64 size)
{
    return REAL(f)->pMethods->xTruncate(REAL(f), size);
}
static int f_sync(sqlite3_file *f, int flags)
{
    if (fault_hit(&io_hook))
        return SQLITE_IOERR_FSYNC;
    return REAL(f)->pMethods->xSync(REAL(f), flags);
}
static int f_size(sqlite3_file *f, sqlite3_int64 *size)
{
    return REAL(f)->pMethods->xFileSize(REAL(f), size);
}
static int f_lock(sqlite3_file *f, int l)
{
    return REAL(f)->pMethods->xLock(REAL(f), l);
}
static int f_unlock(sqlite3_file *f, int l)
{
    return REAL(f)->pMethods->xUnlock(REAL(f), l);
}
static int f_check_reserved(sqlite3_file *f, int *out)
{
    return REAL(f)->pMethods->xCheckReservedLock(REAL(f), out);
}
static int f_control(sqlite3_file *f, int op, void *arg)
{
    return REAL(f)->pMethods->xFileControl(REAL(f), op, arg);
}
static int f_sector(sqlite3_file *f)
{
    return REAL(f)->pMethods->xSectorSize(REAL(f));
}
static int f_devchar(sqlite3_file *f)
{
    return REAL(f)->pMethods->xDeviceCharacteristics(REAL(f));
}
static int f_shm_map(sqlite3_file *f, int pg, int sz, int extend, void volatile **p)
{
    return REAL(f)->pMethods->xShmMap(REAL(f), pg, sz, extend, p);
}
static int f_shm_lock(sqlite3_file *f, int off, int n, int flags)
{
    return REAL(f)->pMethods->xShmLock(REAL(f), off, n, flags);
}
static void f_shm_barrier(sqlite3_file *f)
{
    REAL(f)->pMethods->xShmBarrier(REAL(f));
}
static int f_shm_unmap(sqlite3_file *f, int del)
{
    return REAL(f)->pMethods->xShmUnmap(REAL(f), del);
}
static int f_fetch(sqlite3_file *f, sqlite3_int64 off, int amt, void **p)
{
    return REAL(f)->pMethods->xFetch(REAL(f), off, amt, p);
}
static int f_unfetch(sqlite3_file *f, sqlite3_int64 off, void *p)
{
    return REAL(f)->pMethods->xUnfetch(REAL(f), off, p);
}

/* One table per version of the wrapped file's methods, so SQLite sees
 * exactly the optional methods the real file has. */
#define FAULT_METHODS(v)                                                                     \
    {                                                                                        \
        v, f_close, f_read, f_write, f_truncate, f_sync, f_size, f_lock, f_unlock,            \
            f_check_reserved, f_control, f_sector, f_devchar, v >= 2 ? f_shm_map : NULL,      \
            v >= 2 ? f_shm_lock : NULL, v >= 2 ? f_shm_barrier : NULL,                       \
            v >= 2 ? f_shm_unmap : NULL, v >= 3 ? f_fetch : NULL, v >= 3 ? f_unfetch : NULL  \
    }
static const sqlite3_io_methods fault_methods[3] = {FAULT_METHODS(1), FAULT_METHODS(2),
                                                    FAULT_METHODS(3)};

static int v_open(sqlite3_vfs *vfs, const char *name, sqlite3_file *file, int flags, int *out)
{
    struct fault_file *ff = (struct fault_file *)file;
    ff->real = (sqlite3_file *)(ff + 1);
    memset(ff->real, 0, (size_t)real_vfs->szOsFile);
    int rc = real_vfs->xOpen(real_vfs, name, ff->real, flags, out);
    const sqlite3_io_methods *m = ff->real->pMethods;
    if (m) {
        int v = m->iVersion < 1 ? 1 : m->iVersion > 3 ? 3 : m->iVersion;
        file->pMethods = &fault_methods[v - 1];
    } else {
        file->pMethods = NULL;
    }
    return rc;
}
static int v_delete(sqlite3_vfs *vfs, const char *name, int sync)
{
    return real_vfs->xDelete(real_vfs, name, sync);
}
static int v_access(sqlite3_vfs *vfs, const char *name, int flags, int *out)
{
    return real_vfs->xAccess(real_vfs, name, flags, out);
}
static int v_fullpath(sqlite3_vfs *vfs, const char *name, int n, char *out)
{
    return real_vfs->xFullPathname(real_vfs, name, n, out);
}
static void *v_dlopen(sqlite3_vfs *vfs, const char *name)
{
    return real_vfs->xDlOpen(real_vfs, name);
}
static void v_dlerror(sqlite3_vfs *vfs, int n, char *msg)
{
    real_vfs->xDlError(real_vfs, n, msg);
}
static void (*v_dlsym(sqlite3_vfs *vfs, void *h, const char *sym))(void)
{
    return real_vfs->xDlSym(real_vfs, h, sym);
}
static void v_dlclose(sqlite3_vfs *vfs, void *h)
{
    real_vfs->xDlClose(real_vfs, h);
}
static int v_random(sqlite3_vfs *vfs, int n, char *out)
{
    return real_vfs->xRandomness(real_vfs, n, out);
}
static int v_sleep(sqlite3_vfs *vfs, int us)
{
    return real_vfs->xSleep(real_vfs, us);
}
static int v_time(sqlite3_vfs *vfs, double *t)
{
    return real_vfs->xCurrentTime(real_vfs, t);
}
static int v_lasterror(sqlite3_vfs *vfs, int n, char *msg)
{
    return real_vfs->xGetLastError ? real_vfs->xGetLastError(real_vfs, n, msg) : 0;
}
static int v_time64(sqlite3_vfs *vfs, sqlite3_int64 *t)
{
    return real_vfs->xCurrentTimeInt64(real_vfs, t);
}

static sqlite3_vfs fault_vfs = {
    .iVersion = 2,
    .mxPathname = 0,   /* set from the real one */
    .zName = "cascade-fault",
    .xOpen = v_open,
    .xDelete = v_delete,
    .xAccess = v_access,
    .xFullPathname = v_fullpath,
    .xDlOpen = v_dlopen,
    .xDlError = v_dlerror,
    .xDlSym = v_dlsym,
    .xDlClose = v_dlclose,
    .xRandomness = v_random,
    .xSleep = v_sleep,
    .xCurrentTime = v_time,
    .xGetLastError = v_lasterror,
    .xCurrentTimeInt64 = v_time64,
};

/* --- the malloc hook --------------------------------------------------------- */

static void *m_malloc(int n)
{
    return fault_hit(&mem_hook) ? NULL : real_mem.xMalloc(n);
}
static void m_free(void *p)
{
    real_mem.xFree(p);
}
static void *m_realloc(void *p, int n)
{
    return fault_hit(&mem_hook) ? NULL : real_mem.xRealloc(p, n);
}
static int m_size(void *p)
{
    return real_mem.xSize(p);
}
static int m_roundup(int n)
{
    return real_mem.xRoundup(n);
}
static int m_init(void *app)
{
    return real_mem.xInit(app);
}
static void m_shutdown(void *app)
{
    real_mem.xShutdown(app);
}

/* --- installing, reporting ----------------------------------------------------- */

int db_fault_install(const char *io_spec, const char *malloc_spec, struct err *e)
{
    int rc = parse_spec("CASCADE_FAULT_IO", io_spec, &io_hook, e);
    if (!rc)
        rc = parse_spec("CASCADE_FAULT_MALLOC", malloc_spec, &mem_hook, e);
    if (rc)
        return rc;
    if (mem_hook.on) {
        sqlite3_mem_methods m;
        if (sqlite3_config(SQLITE_CONFIG_GETMALLOC, &real_mem) != SQLITE_OK)
            return err_set(e, ERR_RUNTIME, "CASCADE_FAULT_MALLOC: SQLite is already initialised");
        m = real_mem;
        m.xMalloc = m_malloc;
        m.xFree = m_free;
        m.xRealloc = m_realloc;
        m.xSize = m_size;
        m.xRoundup = m_roundup;
        m.xInit = m_init;
        m.xShutdown = m_shutdown;
        if (sqlite3_config(SQLITE_CONFIG_MALLOC, &m) != SQLITE_OK)
            return err_set(e, ERR_RUNTIME, "CASCADE_FAULT_MALLOC: SQLite is already initialised");
    }
    if (io_hook.on) {
        real_vfs = sqlite3_vfs_find(NULL);   /* initialises SQLite */
        if (!real_vfs)
            return err_set(e, ERR_RUNTIME, "CASCADE_FAULT_IO: SQLite has no default VFS");
        fault_vfs.szOsFile = (int)sizeof(struct fault_file) + real_vfs->szOsFile;
        fault_vfs.mxPathname = real_vfs->mxPathname;
        if (sqlite3_vfs_register(&fault_vfs, 1) != SQLITE_OK)
            return err_set(e, ERR_RUNTIME, "CASCADE_FAULT_IO: cannot register the VFS");
    }
    return 0;
}

static void report_one(FILE *f, const char *what, const struct fault_hook *h)
{
    if (h->on)
        fprintf(f, "cascade: fault injection: %s: %ld calls, failed %ld\n", what, h->calls,
                h->failed);
}

void db_fault_report(FILE *f)
{
    report_one(f, "io", &io_hook);
    report_one(f, "malloc", &mem_hook);
}
