/*
 * Every command of both programs with each kind of bad argument and bad
 * file: a clear message and exit code 2 (bad input; 1 for a file that is
 * not a database: the runtime cannot read it), never a crash.  Under `make test SANITIZE=1` the programs are
 * the AddressSanitizer/UBSan build, so this table also runs every one of
 * these error paths under the sanitizers: a sanitizer report in the output
 * fails the test.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "helpers/ct.h"
#include "helpers/th.h"

struct bad_call {
    const char *args[8];     /* after the program; "@F" is replaced by a file below */
    int code;                /* expected exit code */
    const char *expect;      /* text the message must contain */
};

static const char *file_for(const char *tag, const char *dir)
{
    static char path[8][512];
    static int slot;
    char *out = path[slot++ % 8];
    if (strcmp(tag, "@missing") == 0) {
        snprintf(out, 512, "%s/no/such/file.yaml", dir);
    } else if (strcmp(tag, "@dir") == 0) {
        snprintf(out, 512, "%s", dir);
    } else if (strcmp(tag, "@empty") == 0) {
        snprintf(out, 512, "%s", ct_write(0, dir, "empty.yaml", ""));
    } else if (strcmp(tag, "@binary") == 0) {
        snprintf(out, 512, "%s", ct_write(1, dir, "binary.yaml", "\x01\x02\xff\xfe: [\n\x7f"));
    } else if (strcmp(tag, "@notmap") == 0) {
        snprintf(out, 512, "%s", ct_write(2, dir, "list.yaml", "- 1\n- 2\n"));
    } else if (strcmp(tag, "@badkey") == 0) {
        snprintf(out, 512, "%s", ct_write(3, dir, "badkey.yaml",
                                          "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, "
                                          "3]}, element: Cu}\n"
                                          "potential: {style: sutton_chen}\n"
                                          "md: {timstep: 0.001}\n"));
    } else if (strcmp(tag, "@study_nobase") == 0) {
        snprintf(out, 512, "%s", ct_write(4, dir, "s.yaml", "name: s\nsweep: {grid: {x: [1]}}\n"));
    } else if (strcmp(tag, "@notdb") == 0) {
        snprintf(out, 512, "%s", ct_write(5, dir, "not.db", "this is not a database"));
    } else {
        snprintf(out, 512, "%s", tag);
    }
    return out;
}

static void run_table(const char *prog, const struct bad_call *calls, size_t n)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    for (size_t k = 0; k < n; k++) {
        const char *argv[12] = {prog};
        int m = 1;
        char shown[1024] = "";
        for (int a = 0; calls[k].args[a] && m < 11; a++) {
            const char *s = calls[k].args[a][0] == '@' ? file_for(calls[k].args[a], dir)
                                                       : calls[k].args[a];
            argv[m++] = s;
            strncat(shown, " ", sizeof shown - strlen(shown) - 1);
            strncat(shown, calls[k].args[a], sizeof shown - strlen(shown) - 1);
        }
        argv[m] = NULL;
        char out[16384];
        int rc = ct_exec(dir, NULL, argv, out, sizeof out);
        cr_expect_eq(rc, calls[k].code, "%s%s: exit %d, expected %d: %s", prog, shown, rc,
                     calls[k].code, out);
        cr_expect(strstr(out, calls[k].expect) != NULL, "%s%s: message lacks '%s': %s", prog,
                  shown, calls[k].expect, out);
        cr_expect(!strstr(out, "Sanitizer") && !strstr(out, "runtime error:"),
                  "%s%s: sanitizer report: %s", prog, shown, out);
    }
    ct_rmrf(dir);
}

Test(cli_errors, solver_commands_refuse_bad_arguments_and_files, .timeout = 300)
{
    static const struct bad_call calls[] = {
        {{NULL}, 2, "usage: cascade-solver"},
        {{"frobnicate"}, 2, "frobnicate"},
        {{"run"}, 2, "usage: cascade-solver run"},
        {{"run", "@missing"}, 2, "file.yaml"},
        {{"run", "@dir"}, 2, "error:"},
        {{"run", "@empty"}, 2, "error:"},
        {{"run", "@binary"}, 2, "binary.yaml"},
        {{"run", "@notmap"}, 2, "list.yaml"},
        {{"run", "@badkey"}, 2, "did you mean 'timestep'"},
        {{"run", "@badkey", "--threads", "0"}, 2, "--threads"},
        {{"run", "@badkey", "--threads", "many"}, 2, "--threads"},
        {{"run", "@badkey", "--bogus"}, 2, "--bogus"},
        {{"run", "@badkey", "--out"}, 2, "--out"},
        {{"run", "@badkey", "--restart", "@missing"}, 2, "error:"},
        {{"check"}, 2, "usage: cascade-solver check"},
        {{"check", "@missing"}, 2, "file.yaml"},
        {{"check", "@binary"}, 2, "binary.yaml"},
        {{"check", "@badkey"}, 2, "badkey.yaml:3:"},
        {{"resolve"}, 2, "usage: cascade-solver resolve"},
        {{"resolve", "@missing"}, 2, "file.yaml"},
        {{"resolve", "--key", "@notmap"}, 2, "list.yaml"},
        {{"info", "extra"}, 2, "error:"},
    };
    run_table(th_solver(), calls, sizeof calls / sizeof calls[0]);
}

Test(cli_errors, campaign_commands_refuse_bad_arguments_and_files, .timeout = 300)
{
    static const struct bad_call calls[] = {
        {{NULL}, 2, "usage: cascade"},
        {{"frobnicate"}, 2, "frobnicate"},
        {{"plan"}, 2, "usage: cascade plan"},
        {{"plan", "@missing"}, 2, "file.yaml"},
        {{"plan", "@binary"}, 2, "binary.yaml"},
        {{"plan", "@notmap"}, 2, "list.yaml"},
        {{"plan", "@study_nobase"}, 2, "s.yaml"},
        {{"run"}, 2, "usage: cascade run"},
        {{"run", "@missing"}, 2, "file.yaml"},
        {{"run", "@study_nobase", "--bogus"}, 2, "--bogus"},
        {{"status", "--db", "@missing"}, 2, "file.yaml"},
        {{"status", "--db", "@notdb"}, 1, "not.db"},
        {{"query"}, 2, "usage: cascade query"},
        {{"query", "SELECT 1", "--db", "@notdb"}, 1, "not.db"},
        {{"show"}, 2, "usage: cascade show"},
        {{"show", "abcd", "--db", "@missing"}, 2, "file.yaml"},
        {{"export"}, 2, "usage: cascade export"},
        {{"export", "s", "--db", "@notdb", "--csv"}, 1, "not.db"},
        {{"export", "s", "--format", "xml"}, 2, "give csv or jsonl"},
        {{"retry"}, 2, "usage: cascade retry"},
        {{"report"}, 2, "usage: cascade report"},
        {{"report", "s", "--db", "@missing"}, 2, "file.yaml"},
        {{"report", "--nightly", "--nights", "0"}, 2, "--nights needs an integer"},
        {{"report", "--nightly", "--db", "@notdb"}, 1, "not.db"},
        {{"report", "--nightly", "--db", "@missing"}, 2, "file.yaml"},
        {{"regress"}, 2, "usage: cascade regress"},
        {{"regress", "@missing"}, 2, "file.yaml"},
    };
    run_table(ct_cascade_bin(), calls, sizeof calls / sizeof calls[0]);
}
