/*
 * make reproduce (studies/reproduce.sh, docs/reproduction.md): the table
 * of the papers' numbers is only as good as its spec.  `check` mode plans
 * every study the spec names (quick and full) and requires each row's job
 * selector to pick exactly one job of a study that records the metric --
 * without running anything.  The negative cases show the check can fail.
 */
#include <criterion/criterion.h>
#include <libgen.h>
#include <stdio.h>
#include <string.h>

#include "helpers/ct.h"

static char bindir[4096];

static const char *reproduce_bindir(void)
{
    snprintf(bindir, sizeof bindir, "%s", ct_cascade_bin());
    return dirname(bindir);
}

static int run_check(const char *dir, const char *spec, char *out, size_t len)
{
    char script[4096], env_spec[4200];
    const char *root = getenv("CASCADE_ROOT");
    snprintf(script, sizeof script, "%s/studies/reproduce.sh", root ? root : ".");
    snprintf(env_spec, sizeof env_spec, "REPRODUCE_SPEC=%s", spec ? spec : "");
    const char *const env[] = {env_spec, NULL};
    const char *const argv[] = {"/bin/sh", script, "check", reproduce_bindir(), dir, NULL};
    return ct_exec(dir, spec ? env : NULL, argv, out, len);
}

Test(reproduction, spec_rows_each_pick_one_job_of_a_planned_study, .timeout = 300)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    int rc = run_check(dir, NULL, out, sizeof out);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strstr(out, "every study plans and every row picks one job") != NULL, "%s", out);
    ct_rmrf(dir);
}

/* A selector that matches no job, one that matches several, a metric the
 * study does not record, a paper value that is not a finite number, a
 * quantity given twice and a short row: each is named with its row. */
Test(reproduction, bad_rows_are_named, .timeout = 120)
{
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    const char *spec = ct_write(0, dir, "bad.tsv",
        "paper\twhere\tquantity\tquick\tfull\tjob\tmetric\tpaper_value\tunit\tnote\n"
        "guo2005\tFig. 9\tno such sigma\tguo2005/handshake_packet_quick.yaml\t-\tpacket.sigma=7"
        "\ttransmitted_fraction\t-\t1\tx\n"
        "guo2005\tFig. 9\ttoo many\t-\tguo2005/handshake_packet.yaml\tpacket.sigma=1"
        "\ttransmitted_fraction\t-\t1\tx\n"
        "guo2005\tFig. 4\tnot recorded\tguo2005/handshake_quick.yaml\t-\tsweep"
        "\tno_such_metric\t-\t1\tx\n"
        "guo2005\tFig. 4\tnan value\tguo2005/handshake_quick.yaml\t-\tsweep"
        "\tfront_speed_error\tnan\t1\tx\n"
        "guo2005\tFig. 4\tnan value\tguo2005/handshake_quick.yaml\t-\tsweep"
        "\tfront_speed_error\t1e999x\t1\tx\n"
        "guo2005\tFig. 4\tshort row\n");
    int rc = run_check(dir, spec, out, sizeof out);
    cr_assert_eq(rc, 1, "%s", out);
    cr_assert(strstr(out, "row 1 (no such sigma): job 'packet.sigma=7' picks 0 jobs") != NULL, "%s", out);
    cr_assert(strstr(out, "row 2 (too many): job 'packet.sigma=1' picks 4 jobs") != NULL, "%s", out);
    cr_assert(strstr(out, "row 3 (not recorded): guo2005/handshake_quick.yaml does not record "
                          "no_such_metric") != NULL, "%s", out);
    cr_assert(strstr(out, "row 4 (nan value): paper_value 'nan' is neither - nor a finite number")
              != NULL, "%s", out);
    cr_assert(strstr(out, "row 5 (nan value): the same quantity of guo2005 twice") != NULL, "%s",
              out);
    cr_assert(strstr(out, "row 5 (nan value): paper_value '1e999x' is neither") != NULL, "%s", out);
    cr_assert(strstr(out, "row 6: needs 10 tab-separated fields") != NULL, "%s", out);
    ct_rmrf(dir);
}
