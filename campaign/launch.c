/* launch: run directory, case.yaml and command line of a job attempt. */
#include "launch.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "docpath.h"
#include "util/fault.h"
#include "util/mem.h"
#include "util/wfile.h"
#include "util/yamldoc.h"

struct subst_dirs {
    launch_prep_fn prep_dir;
    void *ctx;
    struct err *e;
};

static const char *subst_dir(void *ctx, const char *name, int is_key)
{
    struct subst_dirs *d = ctx;
    if (!is_key) {
        err_set(d->e, ERR_RUNTIME, "stored case holds ${prep.%s} unresolved", name);
        return NULL;
    }
    return d->prep_dir(d->ctx, name, d->e);
}

static int add_arg(struct launch_spec *L, const char *a)
{
    char **g = mem_realloc(L->argv, (size_t)(L->argc + 2) * sizeof *g);
    if (!g)
        return -1;
    L->argv = g;
    L->argv[L->argc] = mem_strdup(a);
    if (!L->argv[L->argc])
        return -1;
    L->argv[++L->argc] = NULL;
    return 0;
}

int launch_build(struct launch_spec *L, const struct study *s, const struct solver *sv,
                 const char *run_dir, const char *key, const char *case_json,
                 launch_prep_fn prep_dir, void *ctx, const char *resume_dir, struct err *e)
{
    memset(L, 0, sizeof *L);
    snprintf(L->run_dir, sizeof L->run_dir, "%s", run_dir);
    snprintf(L->cwd, sizeof L->cwd, "%s", s->dir);
    L->timeout = s->timeout;
    json_error_t je;
    json_t *doc = json_loads(case_json, 0, &je);
    if (!doc)
        return err_set(e, ERR_RUNTIME, "job %s: stored case is not JSON: %s", key, je.text);
    struct subst_dirs d = {prep_dir, ctx, e};
    if (docpath_refs_replace(doc, subst_dir, &d) != 0) {
        json_decref(doc);
        if (!e->code)
            err_nomem(e, "case");
        return err_prefix(e, "job %s: ", key);
    }
    size_t len = 0;
    FILE *f = fault_alloc_fails() ? NULL : open_memstream(&L->case_yaml, &len);
    if (!f) {
        json_decref(doc);
        return err_nomem(e, "case.yaml");
    }
    fprintf(f, "# job %s of study %s (written by cascade; the key hashes the case with\n"
               "# ${prep:KEY} in place of preparation-job directories)\n",
            key, s->name);
    /* a memory stream fails (ferror) when it cannot grow */
    int bad = yamldoc_write(f, doc) != 0;
    fclose(f);
    json_decref(doc);
    if (s->mpirun_np) {
        char buf[512];
        snprintf(buf, sizeof buf, "%s", s->launcher);
        char *save = NULL;
        for (char *t = strtok_r(buf, " \t", &save); t && !bad; t = strtok_r(NULL, " \t", &save))
            bad = add_arg(L, t);
    }
    char threads[32], case_path[4096 + 16];
    snprintf(threads, sizeof threads, "%ld", s->threads);
    snprintf(case_path, sizeof case_path, "%s/case.yaml", L->run_dir);
    const char *rest[] = {sv->path, "run", case_path, "--out", L->run_dir, "--threads", threads,
                          "--quiet", "--no-progress"};
    for (size_t i = 0; i < sizeof rest / sizeof rest[0] && !bad; i++)
        bad = add_arg(L, rest[i]);
    if (resume_dir && !bad) {
        bad = add_arg(L, "--resume");
        if (!bad)
            bad = add_arg(L, resume_dir);
    }
    if (bad || !L->case_yaml) {
        launch_free(L);
        return err_nomem(e, "command line");
    }
    return 0;
}

static int has_checkpoint(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int found = 0;
    struct dirent *de;
    while (!found && (de = readdir(d)) != NULL) {
        size_t n = strlen(de->d_name);
        found = strncmp(de->d_name, "checkpoint-", 11) == 0 && n > 3 &&
                strcmp(de->d_name + n - 3, ".h5") == 0;
    }
    closedir(d);
    return found;
}

int launch_resume_dir(const char *job_dir, int attempt, char *out, size_t len)
{
    for (int a = attempt - 1; a >= 1; a--) {
        launch_attempt_dir(job_dir, a, out, len);
        if (has_checkpoint(out))
            return 0;
    }
    out[0] = '\0';
    return -1;
}

void launch_free(struct launch_spec *L)
{
    free(L->case_yaml);
    for (int i = 0; L->argv && i < L->argc; i++)
        free(L->argv[i]);
    free(L->argv);
    memset(L, 0, sizeof *L);
}

json_t *launch_to_json(const struct launch_spec *L)
{
    json_t *argv = json_array();
    for (int i = 0; i < L->argc; i++)
        json_array_append_new(argv, json_string(L->argv[i]));
    return json_pack("{s:I, s:I, s:s, s:s, s:s, s:o, s:f}", "job_id", (json_int_t)L->job_id,
                     "run_id", (json_int_t)L->run_id, "run_dir", L->run_dir, "cwd", L->cwd,
                     "case_yaml", L->case_yaml, "argv", argv, "timeout", L->timeout);
}

int launch_from_json(struct launch_spec *L, const json_t *j, struct err *e)
{
    memset(L, 0, sizeof *L);
    const char *rd = json_string_value(json_object_get(j, "run_dir"));
    const char *cwd = json_string_value(json_object_get(j, "cwd"));
    const char *cy = json_string_value(json_object_get(j, "case_yaml"));
    json_t *argv = json_object_get(j, "argv");
    if (!rd || !cwd || !cy || !json_is_array(argv) || json_array_size(argv) == 0)
        return err_set(e, ERR_RUNTIME, "malformed job message");
    L->job_id = (long long)json_integer_value(json_object_get(j, "job_id"));
    L->run_id = (long long)json_integer_value(json_object_get(j, "run_id"));
    snprintf(L->run_dir, sizeof L->run_dir, "%s", rd);
    snprintf(L->cwd, sizeof L->cwd, "%s", cwd);
    L->timeout = json_number_value(json_object_get(j, "timeout"));
    L->case_yaml = mem_strdup(cy);
    int bad = !L->case_yaml;
    size_t i;
    json_t *a;
    json_array_foreach(argv, i, a) if (!bad) bad = add_arg(L, json_string_value(a) ? json_string_value(a) : "");
    if (bad) {
        launch_free(L);
        return err_nomem(e, "job message");
    }
    return 0;
}

/* mkdir that accepts an existing directory, and only a directory; returns
 * 0 or the errno (EEXIST for a file in the way), with e set.  *created (if
 * not NULL) says whether this call made it. */
static int mkdir_one(const char *path, int *created, struct err *e)
{
    if (created)
        *created = 0;
    if (wfile_mkdir(path, 0777) == 0) {
        if (created)
            *created = 1;
        return 0;
    }
    int err = errno;
    struct stat sb;
    if (err == EEXIST && stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return 0;
    if (err == EEXIST) {
        err_set(e, ERR_RUNTIME, "cannot create directory %s: a file of that name is in the way",
                path);
        return EEXIST;
    }
    err_set(e, ERR_RUNTIME, "cannot create directory %s: %s", path, strerror(err));
    return err;
}

/* Create buf and its missing parents, bottom up: the leaf first, and only
 * on ENOENT (or ENOTDIR) its parent, recursively.  Existing ancestors are
 * never touched: a mkdir that fails with EEXIST still takes the parent
 * directory's lock, which in a busy /tmp costs milliseconds per call.  A file
 * in the way is found where its child fails, so the message names it.
 * *created (if not NULL): whether the leaf was made by this call. */
static int mkdirs_up(char *buf, int *created, struct err *e)
{
    int err = mkdir_one(buf, created, e);
    if (err == 0 || (err != ENOENT && err != ENOTDIR))
        return err;
    char *slash = strrchr(buf, '/');
    if (!slash || slash == buf)
        return err;   /* the root or a relative first component: nothing above */
    *slash = '\0';
    int perr = mkdirs_up(buf, NULL, e);
    *slash = '/';
    if (perr)
        return perr;
    return mkdir_one(buf, created, e);
}

int launch_mkdirs(const char *path, struct err *e)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return err_set(e, ERR_RUNTIME, "cannot create directory %.64s...: path too long", path);
    /* trailing slashes would make an empty last component */
    for (size_t n = strlen(buf); n > 1 && buf[n - 1] == '/'; n--)
        buf[n - 1] = '\0';
    return mkdirs_up(buf, NULL, e) ? ERR_RUNTIME : 0;
}

void launch_attempt_dir(const char *job_dir, int attempt, char *out, size_t len)
{
    snprintf(out, len, "%s/attempt-%d", job_dir, attempt);
}

/* Create an attempt directory; *fresh = 1 when this call created it (so it
 * is empty), 0 when it was there already.  A first attempt's job directory
 * is new in nearly every case, so it is made first rather than after the
 * attempt's mkdir failed for want of it (one path walk and one failed call
 * less per job); a later attempt's exists, so its directory is made leaf
 * up as launch_mkdirs does. */
static int mkdir_attempt(const char *run_dir, int *fresh, struct err *e)
{
    char buf[4096];
    *fresh = 0;
    if (snprintf(buf, sizeof buf, "%s", run_dir) >= (int)sizeof buf)
        return err_set(e, ERR_RUNTIME, "cannot create directory %.64s...: path too long",
                       run_dir);
    char *slash = strrchr(buf, '/');
    if (slash && slash != buf && strcmp(slash + 1, "attempt-1") == 0) {
        *slash = '\0';
        int err = mkdirs_up(buf, NULL, e);
        *slash = '/';
        if (err)
            return ERR_RUNTIME;
    }
    return mkdirs_up(buf, fresh, e) ? ERR_RUNTIME : 0;
}

/* case.yaml into a directory this runner has just created: nobody else
 * knows the directory yet, so the file is written in place (no temporary
 * file and rename); the job starts only after it is complete. */
static int write_new_file(const char *path, const char *text, struct err *e)
{
    int fd = fault_write(ENOSPC) != 0 ? -1
                                       : open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0)
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    size_t n = strlen(text), done = 0;
    while (done < n) {
        ssize_t w = fault_write(ENOSPC) != 0 ? -1 : write(fd, text + done, n - done);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            int err = w < 0 ? errno : EIO;
            close(fd);
            unlink(path);
            return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(err));
        }
        done += (size_t)w;
    }
    if (close(fd) != 0) {
        int err = errno;
        unlink(path);
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(err));
    }
    return 0;
}

int launch_setup_dir(const struct launch_spec *L, struct err *e)
{
    int fresh = 0;
    int rc = mkdir_attempt(L->run_dir, &fresh, e);
    if (rc)
        return rc;
    char path[4096 + 16];
    snprintf(path, sizeof path, "%s/case.yaml", L->run_dir);
    if (fresh)
        return write_new_file(path, L->case_yaml, e);
    /* attempt numbers are unique in a database, but runs/ may have served
     * another database (or one deleted since): start from an empty directory */
    DIR *d = opendir(L->run_dir);
    if (!d)
        return err_set(e, ERR_RUNTIME, "%s: %s", L->run_dir, strerror(errno));
    struct dirent *de;
    while ((de = readdir(d))) {
        if (strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0)
            continue;
        char entry[4096 + 256];
        snprintf(entry, sizeof entry, "%s/%s", L->run_dir, de->d_name);
        struct stat sb;
        if (lstat(entry, &sb) == 0 && !S_ISDIR(sb.st_mode))
            unlink(entry);
    }
    closedir(d);
    return wfile_write_text(path, L->case_yaml, 0, e);
}

void launch_remove_dir(const char *run_dir)
{
    char path[4096 + 16];
    snprintf(path, sizeof path, "%s/case.yaml", run_dir);
    unlink(path);
    if (rmdir(run_dir) != 0)
        return;
    /* the job's directory too, when that was its only attempt (rmdir
     * leaves a directory that holds anything else) */
    const char *base = strrchr(run_dir, '/');
    if (base && base != run_dir && snprintf(path, sizeof path, "%.*s", (int)(base - run_dir),
                                            run_dir) < (int)sizeof path)
        rmdir(path);
}

int launch_point_current(const char *run_dir, struct err *e)
{
    const char *base = strrchr(run_dir, '/');
    struct stat sb;
    if (!base || strncmp(base + 1, "attempt-", 8) != 0 || stat(run_dir, &sb) != 0 ||
        !S_ISDIR(sb.st_mode))
        return 0;
    char link[4096 + 64], tmp[4096 + 96];
    snprintf(link, sizeof link, "%.*s/current", (int)(base - run_dir), run_dir);
    /* relative, so the runs directory can be moved or mounted elsewhere */
    if (fault_write(ENOSPC) != 0)
        return err_set(e, ERR_RUNTIME, "cannot create %s: %s", link, strerror(errno));
    /* the job's first link is created in place (symlink is atomic); an
     * existing one is replaced by renaming a new link over it */
    if (symlink(base + 1, link) == 0)
        return 0;
    if (errno != EEXIST)
        return err_set(e, ERR_RUNTIME, "cannot create %s: %s", link, strerror(errno));
    snprintf(tmp, sizeof tmp, "%s.%d", link, (int)getpid());
    unlink(tmp);
    if (fault_write(ENOSPC) != 0 || symlink(base + 1, tmp) != 0)
        return err_set(e, ERR_RUNTIME, "cannot create %s: %s", tmp, strerror(errno));
    if (wfile_rename(tmp, link) != 0) {
        int rc = err_set(e, ERR_RUNTIME, "cannot replace %s: %s", link, strerror(errno));
        unlink(tmp);
        return rc;
    }
    return 0;
}
