/*
 * cascade-solver: runs one simulation from a case file.
 *
 *   cascade-solver run CASE.yaml [--out DIR] [--threads N] [--quiet] [--no-progress]
 *   cascade-solver check CASE.yaml
 *   cascade-solver resolve CASE.yaml | --batch
 *   cascade-solver info
 *
 * Exit codes: 0 success, 1 runtime failure, 2 invalid input or usage,
 * 4 the simulation diverged (result.json says so).
 */
#include <errno.h>
#include <libgen.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/parallel.h"
#include "engine/sim.h"
#include "input/case.h"
#include "input/registry_keys.h"
#include "md/potential.h"
#include "mpm/mpm_material.h"
#include "output/provenance.h"
#include "output/run.h"
#include "scenarios/case_type.h"
#include "util/canon.h"
#include "util/fault.h"

static const char *usage_main =
    "usage: cascade-solver <command> [options]\n"
    "\n"
    "Runs one particle simulation (MD, DPD, MPM, coupled) from a YAML case file.\n"
    "\n"
    "commands:\n"
    "  run CASE.yaml      run the case; outputs go to --out DIR\n"
    "  check CASE.yaml    validate the case (keys, values, files, time step) and exit\n"
    "  resolve CASE.yaml  print the canonical case as JSON (defaults filled in)\n"
    "  resolve --batch    read cases as JSON lines on stdin, print one result line each\n"
    "  info               version, git hash, build flags, libraries; case types, potentials,\n"
    "                     MPM materials and the keys each takes\n"
    "\n"
    "Run 'cascade-solver <command> --help' for a command's options.\n"
    "Exit codes: 0 ok, 1 runtime failure, 2 invalid input, 4 diverged.\n";

static const char *usage_run =
    "usage: cascade-solver run CASE.yaml [--out DIR] [--threads N] [--quiet] [--no-progress]\n"
    "                                    [--restart [DIR|FILE] | --resume DIR]\n"
    "\n"
    "Runs the case.  Writes DIR/result.json (metrics, status, timing), DIR/thermo.csv,\n"
    "DIR/fields.h5 + DIR/fields.xdmf (snapshots for ParaView) and, when asked,\n"
    "DIR/snapshots.xyz (extended XYZ for OVITO) and DIR/checkpoint-STEP.h5\n"
    "(output.checkpoint_every; the newest two are kept).\n"
    "\n"
    "  --out DIR      output directory (default: CASE-out next to the current directory)\n"
    "  --resume DIR   continue from the newest valid checkpoint of this case in DIR when\n"
    "                 there is one, else start from step 0 (the campaign's retries)\n"
    "  --restart [P]  continue from the newest valid checkpoint in directory P (default:\n"
    "                 the --out directory) or from checkpoint file P; the case must be\n"
    "                 the same (same job key).  Same final state as an uninterrupted run,\n"
    "                 bitwise on the same thread count.  Snapshots written before the\n"
    "                 restart are kept as fields.before-STEP.h5\n"
    "  --threads N    OpenMP threads (default: OMP_NUM_THREADS or 1); results do not\n"
    "                 depend on it beyond round-off\n"
    "  --quiet        print errors only\n"
    "  --no-progress  no progress line\n";

static const char *usage_check =
    "usage: cascade-solver check CASE.yaml\n"
    "\n"
    "Validates the case: unknown keys, types and ranges, potential and data files,\n"
    "the particle count and the cutoff against system.max_particles, the time step\n"
    "against the stability bound.  Prints 'ok' or the first error as\n"
    "file:line:column: key: message; exit code 0 or 2.\n";

static const char *usage_resolve =
    "usage: cascade-solver resolve CASE.yaml [--key]\n"
    "       cascade-solver resolve --batch < cases.jsonl\n"
    "\n"
    "Prints the canonical case as JSON: every default filled in, keys sorted, numbers\n"
    "normalised.  Its SHA-256 (first 16 hex digits) is the job key; --key prints it\n"
    "instead.  With --batch, each stdin line is a case as JSON and each output line is\n"
    "  {\"ok\": true, \"key\": \"...\", \"case\": {...}}  or  {\"ok\": false, \"error\": \"...\"}\n"
    "Files named in the cases are not opened (run 'check' for that).\n";

static const char *usage_info =
    "usage: cascade-solver info\n\nPrints as JSON the build and library provenance and\n"
    "every registry -- case types, potential styles, MPM constitutive laws\n"
    "(mpm_materials) -- with a summary each, and under \"keys\" the keys each entry\n"
    "takes with their defaults (\"(required)\" where there is none; \"common\": the\n"
    "keys of every case).\n";

static int wants_help(int argc, char **argv)
{
    for (int i = 0; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    return 0;
}

static int exit_code(int rc)
{
    return rc == ERR_INPUT ? 2 : rc == ERR_DIVERGED ? 4 : rc ? 1 : 0;
}

static int parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || *end || end == s || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

static int cmd_check(int argc, char **argv)
{
    if (wants_help(argc, argv)) {
        fputs(usage_check, stdout);
        return 0;
    }
    if (argc != 1) {
        fputs(usage_check, stderr);
        return 2;
    }
    struct err e = {0};
    struct case_doc cd;
    struct case_resolved cr;
    int rc = case_load_file(&cd, argv[0], &e);
    if (!rc)
        rc = case_resolve(&cd, 0, 1, NULL, &cr, &e);
    if (!rc) {
        printf("ok: %s (%s, %ld particles)\n", argv[0], cr.type->name,
               cr.type->particles(cr.state));
        case_resolved_free(&cr);
    } else {
        fprintf(stderr, "error: %s\n", e.msg);
    }
    case_doc_free(&cd);
    return exit_code(rc);
}

static int resolve_one(struct case_doc *cd, json_t **line)
{
    struct err e = {0};
    struct case_resolved cr;
    int rc = case_resolve(cd, 1, 1, NULL, &cr, &e);
    if (rc) {
        *line = json_pack("{s:b, s:s}", "ok", 0, "error", e.msg);
        return rc;
    }
    case_resolved_free(&cr);
    char key[CANON_KEY_LEN + 1];
    if (canon_key(cd->doc, key) != 0) {
        *line = json_pack("{s:b, s:s}", "ok", 0, "error", "out of memory (case key)");
        return ERR_RUNTIME;
    }
    *line = json_pack("{s:b, s:s, s:O}", "ok", 1, "key", key, "case", cd->doc);
    return 0;
}

static int cmd_resolve(int argc, char **argv)
{
    if (wants_help(argc, argv)) {
        fputs(usage_resolve, stdout);
        return 0;
    }
    int batch = 0, key_only = 0;
    const char *file = NULL;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--batch") == 0)
            batch = 1;
        else if (strcmp(argv[i], "--key") == 0)
            key_only = 1;
        else if (!file && argv[i][0] != '-')
            file = argv[i];
        else {
            fprintf(stderr, "error: unknown option '%s'\n%s", argv[i], usage_resolve);
            return 2;
        }
    }
    if (batch == (file != NULL)) {
        fputs(usage_resolve, stderr);
        return 2;
    }
    if (!batch) {
        struct err e = {0};
        struct case_doc cd;
        int rc = case_load_file(&cd, file, &e);
        json_t *line = NULL;
        if (!rc) {
            rc = resolve_one(&cd, &line);
            if (rc)
                fprintf(stderr, "error: %s\n", json_string_value(json_object_get(line, "error")));
            else if (key_only)
                printf("%s\n", json_string_value(json_object_get(line, "key")));
            else {
                char *text = canon_json(cd.doc);
                printf("%s\n", text);
                free(text);
            }
        } else {
            fprintf(stderr, "error: %s\n", e.msg);
        }
        json_decref(line);
        case_doc_free(&cd);
        return exit_code(rc);
    }
    /* batch: one JSON case per line; every line answered, exit 0 unless I/O fails */
    char *buf = NULL;
    size_t cap = 0;
    ssize_t len;
    long lineno = 0;
    while ((len = getline(&buf, &cap, stdin)) >= 0) {
        lineno++;
        if (len == 0 || buf[strspn(buf, " \t\r\n")] == '\0')
            continue;
        char name[64];
        snprintf(name, sizeof name, "<stdin line %ld>", lineno);
        struct err e = {0};
        struct case_doc cd;
        json_t *line = NULL;
        if (case_load_json(&cd, buf, name, &e) != 0)
            line = json_pack("{s:b, s:s}", "ok", 0, "error", e.msg);
        else
            resolve_one(&cd, &line);
        char *text = canon_json(line);
        printf("%s\n", text);
        free(text);
        json_decref(line);
        case_doc_free(&cd);
    }
    free(buf);
    return fflush(stdout) == 0 ? 0 : 1;
}

static int cmd_info(int argc, char **argv)
{
    if (wants_help(argc, argv)) {
        fputs(usage_info, stdout);
        return 0;
    }
    if (argc > 0) {
        fprintf(stderr, "error: info takes no arguments, got '%s'\n%s", argv[0], usage_info);
        return 2;
    }
    json_t *info = provenance_json();
    json_t *types = json_object();
    for (int i = 0; case_types[i]; i++)
        json_object_set_new(types, case_types[i]->name, json_string(case_types[i]->summary));
    json_object_set_new(info, "case_types", types);
    json_t *pots = json_object();
    for (int i = 0; potential_styles[i].name; i++)
        json_object_set_new(pots, potential_styles[i].name,
                            json_string(potential_styles[i].summary));
    json_object_set_new(info, "potential_styles", pots);
    json_t *mats = json_object();
    for (int i = 0; mpm_material_styles[i].law; i++)
        json_object_set_new(mats, mpm_material_styles[i].law,
                            json_string(mpm_material_styles[i].summary));
    json_object_set_new(info, "mpm_materials", mats);
    /* the keys each entry takes, with its defaults (registry_keys.h) */
    json_t *keys = registry_keys_json();
    if (keys)
        json_object_set_new(info, "keys", keys);
    json_object_set_new(info, "openmp_max_threads", json_integer(omp_get_max_threads()));
    json_dumpf(info, stdout, JSON_INDENT(2) | JSON_SORT_KEYS);
    printf("\n");
    json_decref(info);
    return 0;
}

static int cmd_run_inner(int argc, char **argv, const struct parallel *par);

static int is_directory(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

/* A restart writes fresh output files; the snapshots and frames of the run
 * before it are kept beside them under a name with the checkpoint's step
 * (fields.h5 -> fields.before-NNNNNNNNNN.h5). */
static int keep_previous_outputs(const char *out, const char *ckpt, struct err *e)
{
    const char *base = strrchr(ckpt, '/');
    long step = 0;
    if (sscanf(base ? base + 1 : ckpt, "checkpoint-%ld", &step) != 1)
        step = 0;
    const char *names[][2] = {{"fields", "h5"}, {"fields", "xdmf"}, {"snapshots", "xyz"}};
    for (int k = 0; k < 3; k++) {
        char from[4096 + 8], to[4200];
        snprintf(from, sizeof from, "%s/%s.%s", out, names[k][0], names[k][1]);
        snprintf(to, sizeof to, "%s/%s.before-%010ld.%s", out, names[k][0], step, names[k][1]);
        /* a run that was killed left its streams as NAME.tmp (util/wfile.h) */
        if (access(from, F_OK) != 0)
            strcat(from, ".tmp");
        if (access(from, F_OK) == 0 && rename(from, to) != 0)
            return err_set(e, ERR_RUNTIME, "%s: cannot keep the outputs before the restart: %s",
                           from, strerror(errno));
    }
    return 0;
}

/* Under mpirun every rank reads the same case and usually fails the same
 * way: say it once.  Every rank calls this at the same point with its own
 * rc; rank 0 prints the agreed error (the lowest rank's own, named when it
 * is not rank 0: a file only some nodes see), and every rank returns its
 * class, so none goes on to wait for the others in an exchange and all
 * exit with one code. */
static int report_first_failure(const struct parallel *par, int rc, struct err *e)
{
    rc = parallel_agree_error(par, rc, e);
    if (rc && par->rank == 0)
        fprintf(stderr, "error: %s\n", e->msg);
    return rc;
}

/* MPI (when launched by mpirun) brackets the whole run. */
static int cmd_run(int *argc, char ***argv)
{
    struct parallel par;
    struct err e = {0};
    if (parallel_init(&par, argc, argv, &e) != 0) {
        fprintf(stderr, "error: %s\n", e.msg);
        return 1;
    }
    int rc = cmd_run_inner(*argc - 2, *argv + 2, &par);
    parallel_finalize(&par);
    return rc;
}

static int cmd_run_inner(int argc, char **argv, const struct parallel *par)
{
    if (wants_help(argc, argv)) {
        fputs(usage_run, stdout);
        return 0;
    }
    const char *file = NULL, *out = NULL, *restart = NULL;
    long threads = 0;
    int quiet = 0, progress = 1, want_restart = 0;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            out = argv[++i];
        } else if (strncmp(argv[i], "--restart=", 10) == 0) {
            want_restart = 1;
            restart = argv[i] + 10;
        } else if (strcmp(argv[i], "--resume") == 0 && i + 1 < argc) {
            want_restart = 2;   /* from a checkpoint when there is one */
            restart = argv[++i];
        } else if (strcmp(argv[i], "--restart") == 0) {
            want_restart = 1;
            /* an optional DIR or FILE: a checkpoint file, or a directory
             * when the case file is already given (else it is the case) */
            if (i + 1 < argc && argv[i + 1][0] != '-' &&
                (file || strstr(argv[i + 1], ".h5") || is_directory(argv[i + 1])))
                restart = argv[++i];
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            if (parse_int(argv[++i], 1, 1024, &threads) != 0) {
                if (par->rank == 0)   /* every rank has the same arguments */
                    fprintf(stderr, "error: --threads needs an integer 1..1024, got '%s'\n",
                            argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--quiet") == 0) {
            quiet = 1;
        } else if (strcmp(argv[i], "--no-progress") == 0) {
            progress = 0;
        } else if (!file && argv[i][0] != '-') {
            file = argv[i];
        } else {
            if (par->rank == 0)
                fprintf(stderr, "error: unknown option or missing value '%s'\n%s", argv[i],
                        usage_run);
            return 2;
        }
    }
    if (!file) {
        if (par->rank == 0)
            fputs(usage_run, stderr);
        return 2;
    }
    if (threads == 0) {
        const char *env = getenv("OMP_NUM_THREADS");
        threads = 1;
        if (env && parse_int(env, 1, 1024, &threads) != 0)
            threads = 1;
    }
    char outbuf[4096];
    if (!out) {
        char tmp[4096];
        snprintf(tmp, sizeof tmp, "%s", file);
        char *base = basename(tmp);
        char *dot = strrchr(base, '.');
        if (dot)
            *dot = '\0';
        snprintf(outbuf, sizeof outbuf, "%s-out", base);
        out = outbuf;
    }
    struct err e = {0};
    struct case_doc cd;
    struct case_resolved cr;
    int rc = case_load_file(&cd, file, &e);
    double t0 = timers_now();
    int resolved = 0;
    if (!rc) {
        rc = case_resolve(&cd, 0, (int)threads, par, &cr, &e);
        resolved = rc == 0;
    }
    rc = report_first_failure(par, rc, &e);
    if (rc) {
        if (resolved)
            case_resolved_free(&cr);
        case_doc_free(&cd);
        return exit_code(rc);
    }
    char ckpt_path[4096] = "";
    if (want_restart == 2) {
        /* --resume DIR: the campaign's retry of an attempt that stopped
         * early; a fresh start when DIR holds no checkpoint of this case */
        char key[32];
        if (canon_key(cd.doc, key) != 0) {
            fprintf(stderr, "error: out of memory (case key)\n");
            case_resolved_free(&cr);
            case_doc_free(&cd);
            return exit_code(ERR_RUNTIME);
        }
        struct err e3 = {0};
        if (!cr.type->checkpoints ||
            sim_find_checkpoint(restart, key, ckpt_path, sizeof ckpt_path, &e3) != 0) {
            if (!quiet && par->rank == 0)
                fprintf(stderr, "resume: starting from step 0 (%s)\n",
                        cr.type->checkpoints ? e3.msg : "the case type writes no checkpoints");
            ckpt_path[0] = '\0';
            want_restart = 0;
        }
    }
    if (want_restart == 2 && par->rank == 0)
        rc = keep_previous_outputs(out, ckpt_path, &e);
    if (want_restart == 2 && par->size > 1 && parallel_any(par, rc != 0) && !rc)
        rc = err_set(&e, ERR_RUNTIME, "stopped: rank 0 could not keep the previous outputs");
    if (rc) {
        if (par->rank == 0)
            fprintf(stderr, "error: %s\n", e.msg);
        case_resolved_free(&cr);
        case_doc_free(&cd);
        return exit_code(rc);
    }
    if (want_restart == 1) {
        if (!cr.type->checkpoints)
            rc = err_set(&e, ERR_INPUT, "%s: case type '%s' does not run on the engine with "
                                        "checkpoints yet: --restart is not available for it",
                         file, cr.type->name);
        char key[32];
        if (!rc && canon_key(cd.doc, key) != 0)
            rc = err_nomem(&e, "case key");
        if (!rc)
            rc = sim_find_checkpoint(restart && *restart ? restart : out, key, ckpt_path,
                                     sizeof ckpt_path, &e);
        if (!rc && par->rank == 0)
            rc = keep_previous_outputs(out, ckpt_path, &e);
        rc = report_first_failure(par, rc, &e);
        if (rc) {
            case_resolved_free(&cr);
            case_doc_free(&cd);
            return exit_code(rc);
        }
    }
    /* the restart tests kill a run at an exact step, the way a node failure
     * or a scheduler's time limit would */
    long kill_at = 0;
    const char *kill_env = getenv("CASCADE_SOLVER_KILL_AT_STEP");
    if (kill_env && parse_int(kill_env, 1, 1000000000L, &kill_at) != 0)
        kill_at = 0;
    struct run_options opt = {out, (int)threads, progress, quiet, par->rank,
                              ckpt_path[0] ? ckpt_path : NULL, kill_at, par};
    struct run run;
    rc = run_open(&run, &opt, &cr.output, cd.doc, cr.common.seed, cr.common.title, &e);
    /* rank 0 alone creates the output: when it cannot, the other ranks
     * stop too instead of waiting for it in the run's first exchange */
    int opened = rc == 0;
    rc = report_first_failure(par, rc, &e);
    if (rc && opened)
        run_discard(&run);
    if (rc) {
        case_resolved_free(&cr);
        case_doc_free(&cd);
        return exit_code(rc);
    }
    run.timers.total[TIMER_SETUP] = timers_now() - t0;
    run.timers.calls[TIMER_SETUP] = 1;
    run_log(&run, "cascade-solver %s (%s): %s case '%s', %ld particles, %d rank(s) x %d thread(s), "
                  "out %s",
            provenance_version(), provenance_git_hash(), cr.type->name, file,
            cr.type->particles(cr.state), par->size, (int)threads, out);
    if (par->size > 1 && !cr.type->decomposes &&
        cr.common.parallel.decomposition != DECOMP_REPLICATED && par->rank == 0)
        fprintf(stderr, "note: case type '%s' is not decomposed into bricks yet: each of the "
                        "%d ranks runs the whole case and rank 0 writes (no speed-up; "
                        "docs/parallel.md)\n",
                cr.type->name, par->size);
    rc = cr.type->run(cr.state, &run, &e);
    /* one error for the run, whichever rank met it: rank 0 records and
     * prints it, every rank exits with its code */
    rc = parallel_agree_error(par, rc, &e);
    long steps = 0;
    if (run.steps_run > 0) {   /* the engine, and cases that do not run md.steps, say
                                * how many steps this process ran */
        steps = run.steps_run;
    } else if (cr.type->steps) {
        steps = cr.type->steps(cr.state);
    } else {
        json_t *st = json_object_get(json_object_get(cd.doc, "md"), "steps");
        if (json_is_integer(st))
            steps = (long)json_integer_value(st);
    }
    const char *status = rc == 0 ? "ok" : rc == ERR_DIVERGED ? "diverged" : "failed";
    struct err e2 = {0};
    int rc2 = run_close(&run, status, rc ? e.msg : NULL, steps, cr.type->particles(cr.state), &e2);
    if (rc && par->rank == 0)
        fprintf(stderr, "error: %s\n", e.msg);
    else if (rc2 && par->rank == 0)
        fprintf(stderr, "error: %s\n", e2.msg);
    case_resolved_free(&cr);
    case_doc_free(&cd);
    return exit_code(rc ? rc : rc2);
}

static int run_command(const char *cmd, int *argc, char ***argv)
{
    if (strcmp(cmd, "run") == 0)
        return cmd_run(argc, argv);
    if (strcmp(cmd, "check") == 0)
        return cmd_check(*argc - 2, *argv + 2);
    if (strcmp(cmd, "resolve") == 0)
        return cmd_resolve(*argc - 2, *argv + 2);
    if (strcmp(cmd, "info") == 0)
        return cmd_info(*argc - 2, *argv + 2);
    fprintf(stderr, "error: unknown command '%s'\n\n%s", cmd, usage_main);
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage_main, stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        fputs(usage_main, stdout);
        return 0;
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("cascade-solver %s (%s)\n", provenance_version(), provenance_git_hash());
        return 0;
    }
    /* fault injection for the tests (util/fault.h, docs/fuzzing.md) */
    struct err fe = {0};
    if (fault_install(getenv("CASCADE_FAULT_ALLOC"), getenv("CASCADE_FAULT_WRITE"), &fe) != 0) {
        fprintf(stderr, "error: %s\n", fe.msg);
        return 2;
    }
    int code = run_command(cmd, &argc, &argv);
    if (fault_installed())
        fault_report(stderr, "cascade-solver");
    return code;
}
