/*
 * fake-solver: a stand-in for cascade-solver that the campaign tests drive
 * to fail on request.  It speaks the same contract: `info`, `resolve
 * --batch` (keys from util/canon.h, unknown keys rejected with the same
 * messages through util/cfg.h) and `run CASE.yaml --out DIR` writing
 * DIR/result.json, with exit codes 0 ok, 1 failure, 2 bad input, 4 diverged.
 *
 * Case schema (every key optional):
 *   type: fake   seed: 1   title: ""
 *   fake:
 *     action: ok | sleep | crash | hang | exit | diverge | fail_once | env | slow_once | steps
 *             | probe
 *     seconds: 0        # sleep first (every action)
 *     code: 3           # exit code for 'exit'
 *     message: ""       # exit: a line for stderr before exiting
 *     signal: 11        # crash: the signal it kills itself with
 *     steps: 0          # crash: thermo.csv rows (a "step" column, 1..steps) written first
 *     counter: ""       # crash: a file counting its runs; each earlier run adds a row,
 *                       # so every attempt crashes at a later step
 *     x: 0.0, y: 0.0    # inputs of the metrics x_squared = x^2, sum = x + y, and of
 *                       # the series xs = [0, x, 2x, null] (unit m) and ys = [y]
 *     metrics: 0        # extra metrics m0..m{n-1} (for the speed test)
 *     flag: ""          # fail_once: exit 3 unless this file exists (then create it... see below)
 *                       # slow_once: sleep `seconds` only when it does not exist (creating
 *                       # it first), so a second attempt is quick; writes solver.pid
 *     ignore_term: false  # hang: ignore SIGTERM too (the runner must escalate)
 *     read: ""          # a file that must exist; its size becomes metric read_bytes
 *     write: ""         # a file to write into the output directory
 *     step_seconds: 0   # steps: `steps` steps of this many seconds each, writing
 *     checkpoint_every: 0  # an (empty) checkpoint-<step>.h5 every so many steps; run
 *                       # with --resume DIR it continues from DIR's newest one and
 *                       # result.json says restarted_from_step (as the solver does)
 * CASCADE_FAKE_VERSION overrides the version `info` reports.
 * CASCADE_FAKE_STRICT_FDS=1 makes `info` and `resolve --batch` fail (exit 3,
 * the descriptors named on stderr) when they inherited a descriptor beyond
 * 0-2, so a test can see the runner start them clean.
 */
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "util/canon.h"
#include "util/cfg.h"
#include "util/yamldoc.h"

extern char **environ;

static const char *const actions[] = {"ok",      "sleep",     "crash", "hang",      "exit",
                                      "diverge", "fail_once", "env",   "slow_once", "steps",
                                      "probe",   NULL};
enum {
    A_OK, A_SLEEP, A_CRASH, A_HANG, A_EXIT, A_DIVERGE, A_FAIL_ONCE, A_ENV, A_SLOW_ONCE, A_STEPS,
    A_PROBE
};

struct fake_case {
    long seed;
    int action;
    double seconds, x, y, step_seconds;
    long code, metrics, signal, steps, checkpoint_every;
    int ignore_term;
    const char *flag, *read, *write, *message, *counter;
};

static int fake_read(struct cfg *c, json_t *doc, struct fake_case *fc)
{
    struct cfg_obj root, f;
    const char *type, *title;
    int rc;
    if ((rc = cfg_root(c, doc, &root)) || (rc = cfg_string(&root, "type", "fake", &type)) ||
        (rc = cfg_string(&root, "title", "", &title)) ||
        (rc = cfg_int(&root, "seed", 1, CFG_GE(0), &fc->seed)) ||
        (rc = cfg_section(&root, "fake", &f)) ||
        (rc = cfg_enum(&f, "action", "ok", actions, &fc->action)) ||
        (rc = cfg_real(&f, "seconds", 0.0, CFG_GE(0), &fc->seconds)) ||
        (rc = cfg_int(&f, "code", 3, CFG_RANGE(0, 255), &fc->code)) ||
        (rc = cfg_string(&f, "message", "", &fc->message)) ||
        (rc = cfg_int(&f, "signal", SIGSEGV, CFG_RANGE(1, 64), &fc->signal)) ||
        (rc = cfg_int(&f, "steps", 0, CFG_RANGE(0, 1000000), &fc->steps)) ||
        (rc = cfg_string(&f, "counter", "", &fc->counter)) ||
        (rc = cfg_real(&f, "x", 0.0, CFG_ANY, &fc->x)) ||
        (rc = cfg_real(&f, "y", 0.0, CFG_ANY, &fc->y)) ||
        (rc = cfg_int(&f, "metrics", 0, CFG_RANGE(0, 1000000), &fc->metrics)) ||
        (rc = cfg_bool(&f, "ignore_term", 0, &fc->ignore_term)) ||
        (rc = cfg_string(&f, "flag", "", &fc->flag)) ||
        (rc = cfg_string(&f, "read", "", &fc->read)) ||
        (rc = cfg_string(&f, "write", "", &fc->write)) ||
        (fc->action == A_STEPS &&
         ((rc = cfg_real(&f, "step_seconds", 0.0, CFG_GE(0), &fc->step_seconds)) ||
          (rc = cfg_int(&f, "checkpoint_every", 0, CFG_GE(0), &fc->checkpoint_every)))) ||
        (rc = cfg_close(&f)) ||
        (rc = cfg_close(&root)))
        return rc;
    if (strcmp(type, "fake") != 0)
        return cfg_error_at(c, "type", "the stand-in solver knows only type 'fake'");
    return 0;
}

static int cmd_resolve(void)
{
    char *line = NULL;
    size_t cap = 0;
    long n = 0;
    while (getline(&line, &cap, stdin) >= 0) {
        n++;
        char name[64];
        snprintf(name, sizeof name, "<stdin line %ld>", n);
        struct err e = {0};
        json_error_t je;
        json_t *doc = json_loads(line, 0, &je), *out;
        struct fake_case fc;
        struct cfg c = {name, NULL, &e, ".", 1};
        if (!doc) {
            out = json_pack("{s:b, s:s}", "ok", 0, "error", "invalid JSON");
        } else if (fake_read(&c, doc, &fc) != 0) {
            out = json_pack("{s:b, s:s}", "ok", 0, "error", e.msg);
        } else {
            char key[CANON_KEY_LEN + 1];
            canon_key(doc, key);
            out = json_pack("{s:b, s:s, s:O}", "ok", 1, "key", key, "case", doc);
        }
        char *text = canon_json(out);
        printf("%s\n", text);
        free(text);
        json_decref(out);
        json_decref(doc);
    }
    free(line);
    return 0;
}

/* CASCADE_FAKE_STRICT_FDS: 0 when nothing beyond 0-2 is open, else 3 with
 * the descriptors named on stderr */
static int strict_fds(const char *cmd)
{
    const char *on = getenv("CASCADE_FAKE_STRICT_FDS");
    if (!on || strcmp(on, "1") != 0)
        return 0;
    DIR *d = opendir("/proc/self/fd");
    if (!d) {
        fprintf(stderr, "fake-solver %s: /proc/self/fd: %s\n", cmd, strerror(errno));
        return 3;
    }
    int rc = 0;
    struct dirent *de;
    while ((de = readdir(d)))
        if (de->d_name[0] != '.' && atoi(de->d_name) > 2 && atoi(de->d_name) != dirfd(d)) {
            fprintf(stderr, "fake-solver %s: inherited descriptor %s\n", cmd, de->d_name);
            rc = 3;
        }
    closedir(d);
    return rc;
}

static const char *version(void)
{
    const char *v = getenv("CASCADE_FAKE_VERSION");
    return v && v[0] ? v : "fake-1.0";
}

/* The "NAME:\t<hex>" mask of /proc/self/status (SigBlk, SigIgn), or -1. */
static double status_mask(const char *name)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double v = -1;
    size_t n = strlen(name);
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, name, n) == 0 && line[n] == ':')
            v = (double)strtoull(line + n + 1, NULL, 16);
    if (f)
        fclose(f);
    return v;
}

static void put(json_t *metrics, const char *name, double value)
{
    json_object_set_new(metrics, name, json_pack("{s:f, s:s}", "value", value, "unit", "1"));
}

/* action probe: how the runner set this process up -- signal mask and
 * ignored signals (the masks as numbers; bit s-1 is signal s), whether it
 * leads its own process group, its parent-death signal, descriptors open
 * beyond 0-2, and CASCADE_FAULT_* variables in its environment. */
static void probe_process(json_t *metrics)
{
    put(metrics, "sig_blocked", status_mask("SigBlk"));
    put(metrics, "sig_ignored", status_mask("SigIgn"));
    put(metrics, "own_group", getpgrp() == getpid());
    int pdeath = -1;
    prctl(PR_GET_PDEATHSIG, &pdeath);
    put(metrics, "pdeathsig", pdeath);
    long extra = 0;
    DIR *d = opendir("/proc/self/fd");
    struct dirent *de;
    while (d && (de = readdir(d)))
        if (de->d_name[0] != '.' && atoi(de->d_name) > 2 && atoi(de->d_name) != dirfd(d))
            extra++;
    if (d)
        closedir(d);
    put(metrics, "extra_fds", d ? (double)extra : -1);
    int faults = 0;
    for (char **e = environ; *e; e++)
        faults += strncmp(*e, "CASCADE_FAULT_", 14) == 0;
    put(metrics, "fault_env", faults);
}

static int write_result(const char *dir, json_t *doc, const char *status, const char *message,
                        const struct fake_case *fc, long restarted_from)
{
    json_t *metrics = json_object();
    json_object_set_new(metrics, "x_squared", json_pack("{s:f, s:s}", "value", fc->x * fc->x, "unit", "1"));
    json_object_set_new(metrics, "sum", json_pack("{s:f, s:s}", "value", fc->x + fc->y, "unit", "1"));
    json_object_set_new(metrics, "seed", json_pack("{s:f, s:s}", "value", (double)fc->seed, "unit", "1"));
    for (long i = 0; i < fc->metrics; i++) {
        char name[32];
        snprintf(name, sizeof name, "m%ld", i);
        json_object_set_new(metrics, name, json_pack("{s:f, s:s}", "value", (double)i * 0.5, "unit", "eV"));
    }
    if (fc->action == A_ENV) {
        int n = 0;
        for (char **e = environ; *e; e++)
            if ((strncmp(*e, "OMPI_", 5) == 0 || strncmp(*e, "PMIX_", 5) == 0) &&
                strncmp(*e, "OMPI_ALLOW_RUN_AS_ROOT", 22) != 0)
                n++;
        json_object_set_new(metrics, "mpi_env", json_pack("{s:f, s:s}", "value", (double)n, "unit", "1"));
    }
    if (fc->action == A_PROBE)
        probe_process(metrics);
    if (fc->read[0]) {
        struct stat sb;
        if (stat(fc->read, &sb) == 0)
            json_object_set_new(metrics, "read_bytes",
                                json_pack("{s:f, s:s}", "value", (double)sb.st_size, "unit", "B"));
    }
    json_t *series = json_pack("{s:{s:[f, f, f, n], s:s}, s:{s:[f], s:s}}", "xs", "values", 0.0,
                               fc->x, 2 * fc->x, "unit", "m", "ys", "values", fc->y, "unit", "1");
    char key[CANON_KEY_LEN + 1];
    canon_key(doc, key);
    /* like the solver's timings, the pid makes every run's file its own, so
     * a file one attempt overwrote in another's directory would show */
    json_t *r = json_pack("{s:s, s:o, s:{s:s, s:s}, s:s, s:{s:f, s:i}}", "status", status,
                          "metrics", metrics, "provenance", "version", version(), "git_hash",
                          "standin", "case_key", key, "timing", "peak_rss_mib", 1.0, "pid",
                          (int)getpid());
    json_object_set_new(r, "series", series);
    if (message)
        json_object_set_new(r, "message", json_string(message));
    if (restarted_from >= 0)
        json_object_set_new(r, "restarted_from_step", json_integer(restarted_from));
    char path[4096], tmp[4200];
    snprintf(path, sizeof path, "%s/result.json", dir);
    snprintf(tmp, sizeof tmp, "%s.tmp%d", path, (int)getpid());
    int rc = json_dump_file(r, tmp, JSON_INDENT(1) | JSON_SORT_KEYS);
    json_decref(r);
    if (rc == 0)
        rc = rename(tmp, path);
    return rc;
}

static void nap(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

/* The newest checkpoint-<step>.h5 of dir, or -1. */
static long newest_checkpoint(const char *dir)
{
    DIR *d = opendir(dir);
    long best = -1;
    struct dirent *de;
    while (d && (de = readdir(d))) {
        long step;
        char tail[8];
        if (sscanf(de->d_name, "checkpoint-%ld%4s", &step, tail) == 2 &&
            strcmp(tail, ".h5") == 0 && step > best)
            best = step;
    }
    if (d)
        closedir(d);
    return best;
}

/* action steps: returns the step it continued from, or -1 */
static long run_steps(const struct fake_case *fc, const char *out, const char *resume)
{
    long from = resume ? newest_checkpoint(resume) : -1;
    for (long k = from < 0 ? 1 : from + 1; k <= fc->steps; k++) {
        nap(fc->step_seconds);
        if (fc->checkpoint_every > 0 && k % fc->checkpoint_every == 0) {
            char path[4096 + 64];
            snprintf(path, sizeof path, "%s/checkpoint-%08ld.h5", out, k);
            FILE *f = fopen(path, "w");
            if (f)
                fclose(f);
        }
    }
    return from;
}

static int cmd_run(int argc, char **argv)
{
    const char *file = NULL, *out = ".", *resume = NULL;
    long restarted_from = -1;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            out = argv[++i];
        else if (strcmp(argv[i], "--resume") == 0 && i + 1 < argc)
            resume = argv[++i];
        else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
            i++;
        else if (argv[i][0] != '-')
            file = argv[i];
    }
    if (!file) {
        fprintf(stderr, "usage: fake-solver run CASE.yaml --out DIR\n");
        return 2;
    }
    struct err e = {0};
    json_t *doc;
    struct locmap *locs;
    if (yamldoc_load_file(file, &doc, &locs, &e) != 0) {
        fprintf(stderr, "error: %s\n", e.msg);
        return 2;
    }
    struct fake_case fc;
    struct cfg c = {file, locs, &e, ".", 0};
    if (fake_read(&c, doc, &fc) != 0) {
        fprintf(stderr, "error: %s\n", e.msg);
        return 2;
    }
    mkdir(out, 0777);
    fprintf(stderr, "fake-solver: %s action %s\n", file, actions[fc.action]);
    double seconds = fc.seconds;
    if (fc.action == A_SLOW_ONCE) {
        char path[4096 + 32];
        snprintf(path, sizeof path, "%s/solver.pid", out);
        FILE *f = fopen(path, "w");
        if (f) {
            fprintf(f, "%d\n", (int)getpid());
            fclose(f);
        }
        if (access(fc.flag, F_OK) == 0) {
            seconds = 0;
        } else if ((f = fopen(fc.flag, "w"))) {
            fclose(f);
        }
    }
    if (seconds > 0)
        nap(seconds);
    if (fc.action == A_STEPS)
        restarted_from = run_steps(&fc, out, resume);
    int code = 0;
    if (fc.read[0] && access(fc.read, R_OK) != 0) {
        fprintf(stderr, "error: %s: cannot read '%s'\n", file, fc.read);
        code = 1;
    }
    if (!code && fc.write[0]) {
        char path[4096 + 256];
        snprintf(path, sizeof path, "%s/%s", out, fc.write);
        FILE *f = fopen(path, "w");
        if (f) {
            fprintf(f, "x %.17g\n", fc.x);
            fclose(f);
        }
    }
    if (!code) {
        switch (fc.action) {
        case A_CRASH: {
            long steps = fc.steps;
            if (fc.counter[0]) {
                long runs = 0;
                FILE *f = fopen(fc.counter, "r");
                if (f) {
                    if (fscanf(f, "%ld", &runs) != 1)
                        runs = 0;
                    fclose(f);
                }
                if ((f = fopen(fc.counter, "w"))) {
                    fprintf(f, "%ld\n", runs + 1);
                    fclose(f);
                }
                steps += runs;
            }
            if (steps > 0) {
                /* as the solver writes it: a comment, the header, flushed rows */
                char path[4096 + 32];
                snprintf(path, sizeof path, "%s/thermo.csv", out);
                FILE *f = fopen(path, "w");
                if (f) {
                    fprintf(f, "# fake-solver\ntime_ps,step,pe_eV\n");
                    for (long k = 1; k <= steps; k++)
                        fprintf(f, "%g,%ld,%g\n", 0.001 * (double)k, k, -1.0 * (double)k);
                    fclose(f);
                }
            }
            fprintf(stderr, "fake-solver: crashing now\n");
            signal((int)fc.signal, SIG_DFL);
            kill(getpid(), (int)fc.signal);
            break;
        }
        case A_HANG: {
            if (fc.ignore_term)
                signal(SIGTERM, SIG_IGN);
            pid_t child = fork();
            if (child == 0) {
                for (;;)
                    pause();
            }
            char path[4096 + 32];
            snprintf(path, sizeof path, "%s/grandchild.pid", out);
            FILE *f = fopen(path, "w");
            if (f) {
                fprintf(f, "%d\n", (int)child);
                fclose(f);
            }
            fprintf(stderr, "fake-solver: hanging (child %d)\n", (int)child);
            for (;;)
                pause();
        }
        case A_EXIT:
            if (fc.message[0])
                fprintf(stderr, "%s\n", fc.message);
            fprintf(stderr, "fake-solver: exiting with code %ld as asked\n", fc.code);
            code = (int)fc.code;
            break;
        case A_DIVERGE:
            write_result(out, doc, "diverged", "diverged: non-finite energy at step 7 (fake)", &fc, -1);
            fprintf(stderr, "error: diverged: non-finite energy at step 7 (fake)\n");
            code = 4;
            break;
        case A_FAIL_ONCE:
            if (access(fc.flag, F_OK) != 0) {
                FILE *f = fopen(fc.flag, "w");
                if (f)
                    fclose(f);
                fprintf(stderr, "fake-solver: failing the first time\n");
                code = 3;
                break;
            }
            /* fall through */
        default:
            code = write_result(out, doc, "ok", NULL, &fc, restarted_from) == 0 ? 0 : 1;
        }
    }
    json_decref(doc);
    locmap_destroy(&locs);
    return code;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "info") == 0) {
        if (strict_fds("info"))
            return 3;
        printf("{\"version\": \"%s\", \"git_hash\": \"standin\", \"case_types\": {\"fake\": "
               "\"stand-in for tests\"}}\n",
               version());
        return 0;
    }
    if (argc >= 3 && strcmp(argv[1], "resolve") == 0 && strcmp(argv[2], "--batch") == 0)
        return strict_fds("resolve") ? 3 : cmd_resolve();
    if (argc >= 2 && strcmp(argv[1], "run") == 0)
        return cmd_run(argc - 2, argv + 2);
    fprintf(stderr, "usage: fake-solver info | resolve --batch | run CASE.yaml --out DIR\n");
    return 2;
}
