/* ct: campaign test helpers. */
#define _GNU_SOURCE
#include "ct.h"

#include <criterion/criterion.h>
#include <fcntl.h>
#include <ftw.h>
#include <grp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

const char *ct_cascade_bin(void)
{
    const char *s = getenv("CASCADE_BIN");
    return s ? s : "bin/cascade";
}

const char *ct_standin(void)
{
    const char *s = getenv("CASCADE_STANDIN");
    return s ? s : "bin/fake-solver";
}

void ct_mkdir(char *out, size_t len)
{
    snprintf(out, len, "/tmp/cascade-ct-XXXXXX");
    cr_assert_not_null(mkdtemp(out));
}

static int rm_one(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

void ct_rmrf(const char *dir)
{
    if (strncmp(dir, "/tmp/cascade-ct-", 16) == 0)
        nftw(dir, rm_one, 16, FTW_DEPTH | FTW_PHYS);
}

const char *ct_write(int slot, const char *dir, const char *name, const char *text)
{
    static char paths[8][512];
    snprintf(paths[slot], sizeof paths[slot], "%s/%s", dir, name);
    FILE *f = fopen(paths[slot], "w");
    cr_assert_not_null(f, "cannot write %s", paths[slot]);
    fputs(text, f);
    fclose(f);
    return paths[slot];
}

void ct_write_flaky_study(const char *dir)
{
    char text[1024];
    snprintf(text, sizeof text,
             "name: flaky\n"
             "base: {fake: {action: fail_once}}\n"
             "sweep: {zip: {fake.x: [1, 2], fake.flag: [%s/flag1, %s/flag2]}}\n"
             "retries: 1\n",
             dir, dir);
    ct_write(0, dir, "flaky.yaml", text);
}

static void child_setup(const char *dir, const char *const *env)
{
    if (chdir(dir) != 0)
        _exit(126);
    for (int i = 0; env && env[i]; i++)
        putenv((char *)env[i]);
}

/* Set between fork and exec in ct_cascade_unprivileged's child only. */
static int drop_privileges(void)
{
    if (geteuid() != 0)
        return 0;
    if (setgroups(0, NULL) != 0 || setgid(65534) != 0 || setuid(65534) != 0)
        return -1;
    return 0;
}

int ct_wait(pid_t pid)
{
    int status;
    while (waitpid(pid, &status, 0) < 0) {
    }
    if (WIFSIGNALED(status))
        return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

static int exec_as(const char *dir, const char *const *env, const char *const *argv, char *out,
                   size_t len, int unprivileged)
{
    int p[2];
    cr_assert_eq(pipe(p), 0);
    pid_t pid = fork();
    cr_assert(pid >= 0);
    if (pid == 0) {
        child_setup(dir, env);
        if (unprivileged && drop_privileges() != 0)
            _exit(125);
        dup2(p[1], 1);
        dup2(p[1], 2);
        close(p[0]);
        close(p[1]);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    close(p[1]);
    size_t n = 0;
    char buf[4096];
    ssize_t got;
    while ((got = read(p[0], buf, sizeof buf)) > 0) {
        if (out && n + 1 < len) {
            size_t take = (size_t)got < len - 1 - n ? (size_t)got : len - 1 - n;
            memcpy(out + n, buf, take);
            n += take;
        }
    }
    close(p[0]);
    if (out)
        out[n] = '\0';
    return ct_wait(pid);
}

int ct_exec(const char *dir, const char *const *env, const char *const *argv, char *out, size_t len)
{
    return exec_as(dir, env, argv, out, len, 0);
}

int ct_cascade(const char *dir, const char *const *env, char *out, size_t len, ...)
{
    const char *argv[64];
    int n = 0;
    argv[n++] = ct_cascade_bin();
    va_list ap;
    va_start(ap, len);
    const char *a;
    while ((a = va_arg(ap, const char *)) && n < 63)
        argv[n++] = a;
    va_end(ap);
    argv[n] = NULL;
    return ct_exec(dir, env, argv, out, len);
}

int ct_cascade_unprivileged(const char *dir, char *out, size_t len, ...)
{
    const char *argv[64];
    int n = 0;
    argv[n++] = ct_cascade_bin();
    va_list ap;
    va_start(ap, len);
    const char *a;
    while ((a = va_arg(ap, const char *)) && n < 63)
        argv[n++] = a;
    va_end(ap);
    argv[n] = NULL;
    return exec_as(dir, NULL, argv, out, len, 1);
}

pid_t ct_spawn(const char *dir, const char *const *env, const char *const *argv, const char *log)
{
    pid_t pid = fork();
    cr_assert(pid >= 0);
    if (pid == 0) {
        child_setup(dir, env);
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    return pid;
}

sqlite3 *ct_db(const char *dir)
{
    char path[512];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    sqlite3 *db = NULL;
    cr_assert_eq(sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL), SQLITE_OK,
                 "cannot open %s", path);
    sqlite3_busy_timeout(db, 10000);
    return db;
}

static sqlite3_stmt *first_row(sqlite3 *db, const char *sql)
{
    sqlite3_stmt *st;
    cr_assert_eq(sqlite3_prepare_v2(db, sql, -1, &st, NULL), SQLITE_OK, "%s: %s", sql,
                 sqlite3_errmsg(db));
    cr_assert_eq(sqlite3_step(st), SQLITE_ROW, "no row from: %s", sql);
    return st;
}

long long ct_int(sqlite3 *db, const char *sql)
{
    sqlite3_stmt *st = first_row(db, sql);
    long long v = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    return v;
}

double ct_real(sqlite3 *db, const char *sql)
{
    sqlite3_stmt *st = first_row(db, sql);
    double v = sqlite3_column_double(st, 0);
    sqlite3_finalize(st);
    return v;
}

void ct_text(sqlite3 *db, const char *sql, char *out, size_t len)
{
    sqlite3_stmt *st = first_row(db, sql);
    const char *t = (const char *)sqlite3_column_text(st, 0);
    snprintf(out, len, "%s", t ? t : "");
    sqlite3_finalize(st);
}
