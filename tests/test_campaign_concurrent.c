/*
 * Two `cascade run` processes on one database and one study at the same
 * time: leases taken in BEGIN IMMEDIATE transactions mean no job is ever run
 * twice -- each job has exactly one run, all done, and both runners return
 * when the study is complete.  Both do work (the jobs are shared out).
 * Heartbeats renew the leases, so a job running longer than the lease is
 * not taken over by the other runner.
 */
#include <criterion/criterion.h>
#include <stdio.h>

#include "helpers/ct.h"

Test(campaign_concurrent, two_runners_never_run_a_job_twice, .timeout = 90)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "shared.yaml",
             "name: shared\n"
             "base: {fake: {action: sleep, seconds: 0.05}}\n"
             "sweep:\n"
             "  grid:\n"
             "    fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]\n"
             "    fake.y: [1, 2, 3]\n");
    const char *argv[] = {ct_cascade_bin(), "run", "shared.yaml", "--solver", ct_standin(),
                          "--jobs", "2", "--quiet", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    pid_t b = ct_spawn(dir, NULL, argv, "b.log");
    cr_assert_eq(ct_wait(a), 0, "runner a failed (see %s/a.log)", dir);
    cr_assert_eq(ct_wait(b), 0, "runner b failed (see %s/b.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), 36);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 36, "some job was run twice");
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT job_id) FROM runs WHERE status = 'done'"), 36);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT runner) FROM runs"), 2,
                 "one runner did all the work: the test shows nothing");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_concurrent, heartbeats_keep_long_jobs, .timeout = 90)
{
    /* jobs of 3.2 s under 2 s leases: only the heartbeats (every third of the
     * lease) stop the second runner from taking over jobs the first still
     * runs (2 s leaves room for a heavily loaded machine) */
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "long.yaml",
             "name: long\n"
             "base: {fake: {action: sleep, seconds: 3.2}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "long.yaml", "--solver", ct_standin(),
                          "--jobs", "2", "--lease", "2", "--quiet", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    pid_t b = ct_spawn(dir, NULL, argv, "b.log");
    cr_assert_eq(ct_wait(a), 0, "runner a failed (see %s/a.log)", dir);
    cr_assert_eq(ct_wait(b), 0, "runner b failed (see %s/b.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 4, "a running job was taken over");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 4);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_concurrent, two_runners_share_a_preparation_job, .timeout = 90)
{
    /* one runner takes the preparation job; the other waits for it (it is
     * leased elsewhere) and then takes its share of the jobs that read it */
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "prep.yaml",
             "name: prep\n"
             "base: {fake: {action: sleep, seconds: 0.1, read: '${prep.p}/state.txt'}}\n"
             "prep:\n"
             "  p: {base: {fake: {action: sleep, seconds: 0.8, write: state.txt}}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "prep.yaml", "--solver", ct_standin(),
                          "--jobs", "2", "--quiet", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    pid_t b = ct_spawn(dir, NULL, argv, "b.log");
    cr_assert_eq(ct_wait(a), 0, "runner a failed (see %s/a.log)", dir);
    cr_assert_eq(ct_wait(b), 0, "runner b failed (see %s/b.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 13, "some job was run twice");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 13);
    /* every sweep job read the file the preparation job wrote, after it finished */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'read_bytes' AND "
                            "value > 0"),
                 12);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs s JOIN jobs j ON j.id = s.job_id, "
                            "runs p JOIN jobs pj ON pj.id = p.job_id AND pj.kind = 'prep' "
                            "WHERE j.kind = 'sweep' AND s.started < p.finished"),
                 0, "a job started before the preparation job it reads had finished");
    sqlite3_close(db);
    ct_rmrf(dir);
}
