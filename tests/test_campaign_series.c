/*
 * Series from result.json in the database (study key `series:`, table
 * series_values, db/migrations/0009_series_values.sql): the stand-in solver
 * writes xs = [0, x, 2x, null] (m) and ys = [y]; a study listing xs gets
 * one row per value in order with its unit, the null as NULL, and no row
 * of ys; a study without `series:` records none; a bad `series:` is
 * refused with file, line and column before anything is written.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "helpers/ct.h"

Test(campaign_series, listed_series_are_recorded_in_order, .timeout = 60)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: s\n"
             "base: {fake: {action: ok, y: 4}}\n"
             "sweep:\n"
             "  grid:\n"
             "    fake.x: [1.5, 3]\n"
             "series: [xs]\n");
    ct_write(1, dir, "plain.yaml",
             "name: plain\n"
             "base: {fake: {action: ok, y: 5}}\n"
             "sweep:\n"
             "  grid:\n"
             "    fake.x: [7]\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "plain.yaml", "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM series_values"), 8, "two runs of four values");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM series_values WHERE name <> 'xs'"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM series_values WHERE unit <> 'm'"), 0);
    /* x = 3: 0, 3, 6, NULL in idx order */
    const char *one = "SELECT %s FROM series_values v JOIN runs r ON r.id = v.run_id "
                      "JOIN job_params p ON p.job_id = r.job_id AND p.name = 'fake.x' "
                      "WHERE p.value = 3 AND v.idx = %d";
    char sql[512];
    for (int i = 0; i < 3; i++) {
        snprintf(sql, sizeof sql, one, "v.value", i);
        cr_assert_float_eq(ct_real(db, sql), 3.0 * i, 1e-12, "idx %d", i);
    }
    snprintf(sql, sizeof sql, one, "v.value IS NULL", 3);
    cr_assert_eq(ct_int(db, sql), 1, "null stays NULL");
    sqlite3_close(db);

    /* refused: not a list, a name twice */
    ct_write(2, dir, "bad.yaml",
             "name: bad\n"
             "base: {fake: {action: ok}}\n"
             "series: [xs, xs]\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "bad.yaml", "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:3:") && strstr(out, "series[1]") && strstr(out, "listed twice"),
              "%s", out);
    ct_write(2, dir, "bad.yaml",
             "name: bad\n"
             "base: {fake: {action: ok}}\n"
             "series: xs\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "bad.yaml", "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:3:") && strstr(out, "must be a list"), "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM studies WHERE name = 'bad'"), 0);
    sqlite3_close(db);
    ct_rmrf(dir);
}
