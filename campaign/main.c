/*
 * cascade: the campaign runner.  Expands studies into jobs, runs
 * cascade-solver for each (locally, or on the ranks of `mpirun -np N cascade
 * run`), and records the results in SQLite.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "build_info.h"
#include "cli.h"
#include "db_fault.h"
#include "util/fault.h"

static const char *usage =
    "usage: cascade <command> [options]\n"
    "\n"
    "Runs parameter studies with cascade-solver and records the results in SQLite.\n"
    "\n"
    "commands:\n"
    "  plan STUDY.yaml           print the jobs and their keys; runs nothing\n"
    "  run STUDY.yaml            run the jobs not yet done (resumes; also under mpirun)\n"
    "  status [STUDY]            jobs done / failed / running / pending per study\n"
    "  query \"SQL\"               read-only SQL on the results database\n"
    "  show KEY                  one job: parameters, attempts, metrics, files\n"
    "  export STUDY              one row per job: parameters and metrics (CSV or JSON lines)\n"
    "  retry STUDY [--failed]    run the study's jobs again (or only the failed ones)\n"
    "  cancel STUDY              scancel what the study has queued or running in Slurm\n"
    "  report STUDY              convergence report (Markdown + HTML with figures)\n"
    "  regress STUDY.yaml        rerun a study and compare it with its baseline\n"
    "  import STUDY FILE.csv     reference values of an external source (experiment, ...)\n"
    "\n"
    "The database is ./" CASCADE_DB_DEFAULT " unless --db FILE is given; its tables are\n"
    "described in db/README.md.  'cascade <command> --help' shows a command's options;\n"
    "'cascade --version' prints the version and the git commit it was built from.\n"
    "Exit codes: 0 ok, 1 a job failed or a runtime error, 2 bad input, 130 interrupted.\n";

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage, stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        fputs(usage, stdout);
        return 0;
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("cascade %s (%s)\n", CASCADE_VERSION, CASCADE_GIT_HASH);
        return 0;
    }
    static const struct {
        const char *name;
        int (*fn)(int, char **);
    } cmds[] = {{"plan", cmd_plan},     {"run", cmd_run},       {"status", cmd_status},
                {"query", cmd_query},   {"show", cmd_show},     {"export", cmd_export},
                {"retry", cmd_retry},   {"report", cmd_report}, {"regress", cmd_regress},
                {"import", cmd_import}, {"cancel", cmd_cancel}};
    /* fault injection for the tests (docs/fuzzing.md): SQLite's writes and
     * allocations (campaign/db_fault.h), read here, once, before SQLite is
     * first used; Cascade's own allocations and file writes (util/fault.h) */
    const char *fault_io = getenv("CASCADE_FAULT_IO"), *fault_mem = getenv("CASCADE_FAULT_MALLOC");
    int faults = (fault_io && fault_io[0]) || (fault_mem && fault_mem[0]);
    if (faults) {
        struct err e = {0};
        if (db_fault_install(fault_io, fault_mem, &e) != 0) {
            fprintf(stderr, "error: %s\n", e.msg);
            return cli_exit_code(e.code);
        }
    }
    {
        struct err e = {0};
        if (fault_install(getenv("CASCADE_FAULT_ALLOC"), getenv("CASCADE_FAULT_WRITE"), &e) != 0) {
            fprintf(stderr, "error: %s\n", e.msg);
            return cli_exit_code(e.code);
        }
    }
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (strcmp(cmd, cmds[i].name) == 0) {
            int code = cmds[i].fn(argc - 2, argv + 2);
            if (faults)
                db_fault_report(stderr);
            fault_report(stderr, "cascade");
            return code;
        }
    fprintf(stderr, "error: unknown command '%s'\n\n%s", cmd, usage);
    return 2;
}
