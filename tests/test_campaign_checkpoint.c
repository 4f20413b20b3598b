/*
 * A campaign job that stops early continues from its checkpoint on the
 * next attempt.  The real solver kills itself at step 130 of its first
 * attempt (CASCADE_SOLVER_KILL_AT_STEP: a node failure at an exact step);
 * the runner records the crash, retries, and passes the first attempt's
 * directory with --resume: the second attempt continues from the
 * checkpoint of step 120 (runs.resumed_from_step), and its metrics are
 * those of the same case run uninterrupted, bit for bit.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/ct.h"

static const char *case_body =
    "  seed: 7\n"
    "  system: {lattice: {style: fcc, a: 3.615, cells: [4, 4, 4]}, element: Cu}\n"
    "  potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
    "  md: {timestep: 0.002, steps: 300, temperature: 600,\n"
    "       thermostat: {style: langevin, temperature: 500, tau: 0.1}}\n"
    "  output: {thermo_every: 25, hdf5: false, checkpoint_every: 40}\n";

Test(campaign_checkpoint, retry_continues_from_the_checkpoint, .timeout = 300)
{
    char dir[64], out[65536], study[2048], solo[2048];
    ct_mkdir(dir, sizeof dir);
    snprintf(study, sizeof study,
             "name: ck\nbase:\n%s"
             "sweep: {grid: {seed: [7]}}\n"
             "metrics: [pe, etotal, temperature_mean, energy_drift_rate]\n"
             "retries: 2\n",
             case_body);
    ct_write(0, dir, "ck.yaml", study);
    const char *env[] = {"CASCADE_SOLVER_KILL_AT_STEP=130", NULL};
    int rc = ct_cascade(dir, env, out, sizeof out, "run", "ck.yaml", "--quiet", NULL);
    cr_assert_eq(rc, 0, "the retry should finish the job: %s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 2);
    char status[32];
    ct_text(db, "SELECT status FROM runs WHERE attempt = 1", status, sizeof status);
    cr_assert_str_eq(status, "crashed");
    cr_assert_eq(ct_int(db, "SELECT signal FROM runs WHERE attempt = 1"), 9);
    ct_text(db, "SELECT status FROM runs WHERE attempt = 2", status, sizeof status);
    cr_assert_str_eq(status, "done");
    cr_assert_eq(ct_int(db, "SELECT resumed_from_step FROM runs WHERE attempt = 2"), 120);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE attempt = 1 AND "
                            "resumed_from_step IS NOT NULL"),
                 0);

    /* the same case, uninterrupted, outside the campaign */
    snprintf(solo, sizeof solo, "%s", case_body);
    char *text = malloc(strlen(solo) + 1), *w = text;
    for (const char *r = solo; *r;) {   /* drop the study's two-space indent */
        if (r[0] == ' ' && r[1] == ' ' && (r == solo || r[-1] == '\n'))
            r += 2;
        else
            *w++ = *r++;
    }
    *w = '\0';
    const char *path = ct_write(1, dir, "solo.yaml", text);
    free(text);
    char outdir[128];
    snprintf(outdir, sizeof outdir, "%s/solo", dir);
    const char *argv[] = {getenv("CASCADE_SOLVER"), "run", path, "--out", outdir, "--quiet",
                          "--threads", "1", NULL};
    rc = ct_exec(dir, NULL, argv, out, sizeof out);
    cr_assert_eq(rc, 0, "%s", out);
    char rp[192];
    snprintf(rp, sizeof rp, "%s/result.json", outdir);
    json_t *r = json_load_file(rp, 0, NULL);
    cr_assert_not_null(r);
    const char *names[] = {"pe", "etotal", "temperature_mean", "energy_drift_rate"};
    for (int k = 0; k < 4; k++) {
        double want = json_real_value(
            json_object_get(json_object_get(json_object_get(r, "metrics"), names[k]), "value"));
        char sql[256];
        snprintf(sql, sizeof sql,
                 "SELECT value FROM metrics m JOIN runs d ON d.id = m.run_id "
                 "WHERE d.attempt = 2 AND m.name = '%s'",
                 names[k]);
        double got = ct_real(db, sql);
        cr_assert(memcmp(&got, &want, sizeof got) == 0,
                  "%s: %.17g after the resumed attempt, %.17g uninterrupted", names[k], got, want);
    }
    json_decref(r);
    sqlite3_close(db);
    ct_rmrf(dir);
}
