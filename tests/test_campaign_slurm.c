/*
 * The Slurm backend against a real Slurm: every test that submits starts a
 * one-node cluster of its own (tests/helpers/slurmfx.h: munged, slurmctld,
 * slurmd under a temporary directory, ports of its own) and stops exactly
 * those daemons at the end.  When the daemons cannot start on this machine
 * the test is skipped with the command and its message.
 *
 * sbatch is counted through a wrapper put first in PATH: it appends its
 * arguments to a log and runs the real one.
 */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "campaign/launch.h"
#include "campaign/slurm_script.h"
#include "campaign/slurm_spec.h"
#include "campaign/slurm_state.h"
#include "helpers/ct.h"
#include "helpers/slurmfx.h"

/* each test runs in a process of its own: one cluster per test */
static struct slurmfx fx;

static void stop_cluster(void)
{
    slurmfx_stop(&fx);
}

static void start_cluster(const struct slurmfx_opts *o)
{
    if (slurmfx_start(&fx, o) != 0) {
        char why[2048];
        snprintf(why, sizeof why, "%s", fx.skip);
        slurmfx_stop(&fx);
        fprintf(stderr, "campaign_slurm: skipped, the test cluster did not start: %s\n", why);
        cr_skip_test("the test cluster did not start: %s", why);
    }
}

/* A wrapper for sbatch first in PATH (dir/bin), logging to dir/sbatch.log;
 * env receives "PATH=..." (static storage per call site: one at a time). */
static const char *wrap_sbatch(const char *dir)
{
    static char path_env[8192];
    char bin[256], script[1024];
    snprintf(bin, sizeof bin, "%s/bin", dir);
    mkdir(bin, 0755);
    snprintf(script, sizeof script,
             "#!/bin/sh\nprintf '%%s\\n' \"$*\" >> '%s/sbatch.log'\nexec /usr/bin/sbatch \"$@\"\n",
             dir);
    const char *p = ct_write(7, bin, "sbatch", script);
    chmod(p, 0755);
    snprintf(path_env, sizeof path_env, "PATH=%s:%s", bin, getenv("PATH"));
    return path_env;
}

/* sbatch calls that submitted (not --test-only) */
static int submissions(const char *dir)
{
    char path[256], line[4096];
    snprintf(path, sizeof path, "%s/sbatch.log", dir);
    FILE *f = fopen(path, "r");
    int n = 0;
    while (f && fgets(line, sizeof line, f))
        n += strstr(line, "--test-only") == NULL;
    if (f)
        fclose(f);
    return n;
}

static int count_lines(const char *text)
{
    int n = 0;
    for (const char *c = text; *c; c++)
        n += *c == '\n';
    return n;
}

/* --- units: values and scripts ----------------------------------------------- */

Test(campaign_slurm, time_values)
{
    cr_assert_eq(slurm_time_seconds("90"), 5400);
    cr_assert_eq(slurm_time_seconds("1:30"), 90);
    cr_assert_eq(slurm_time_seconds("01:30:00"), 5400);
    cr_assert_eq(slurm_time_seconds("2-12"), 2 * 86400 + 12 * 3600);
    cr_assert_eq(slurm_time_seconds("1-00:10"), 86400 + 600);
    cr_assert_eq(slurm_time_seconds("1-00:10:05"), 86400 + 605);
    const char *bad[] = {"", "1:60", "1:2:3:4", "x", "1-", "1-25", "10\n#SBATCH", "1:00$(x)", NULL};
    for (int i = 0; bad[i]; i++)
        cr_assert_eq(slurm_time_seconds(bad[i]), -1, "'%s' accepted", bad[i]);
    char buf[32];
    slurm_time_format(86400 + 3661, buf, sizeof buf);
    cr_assert_str_eq(buf, "1-01:01:01");
    cr_assert_float_eq(slurm_elapsed_seconds("1:02"), 62.0, 1e-9);
    cr_assert_float_eq(slurm_elapsed_seconds("1-02:03:04"), 93784.0, 1e-9);
}

Test(campaign_slurm, squeue_lines_and_states)
{
    struct slurm_task t;
    cr_assert_eq(slurm_parse_task("12_3|TIMEOUT|36608|1:15|2026-11-25T14:38:04|"
                                  "2026-11-25T14:39:19|TimeLimit|node[1-2]",
                                  &t),
                 0);
    cr_assert_str_eq(t.id, "12_3");
    cr_assert_str_eq(t.state, "TIMEOUT");
    cr_assert_eq(t.exit_status, 36608);
    cr_assert_float_eq(t.elapsed_s, 75.0, 1e-9);
    cr_assert_float_eq(t.end - t.start, 75.0, 1e-9);
    cr_assert_str_eq(t.nodes, "node[1-2]");
    cr_assert(slurm_state_final("OUT_OF_MEMORY"));
    cr_assert(!slurm_state_final("COMPLETING"));
    cr_assert(!slurm_state_final("PENDING"));
    cr_assert_neq(slurm_parse_task("garbage", &t), 0);

    /* accounting: the job line and its steps' MaxRSS */
    int step;
    double rss;
    cr_assert_eq(slurm_parse_sacct("12_3.batch|COMPLETED|0:0|00:01:05|node1|2026-11-25T14:38:04|"
                                   "2026-11-25T14:39:09|2048K",
                                   &t, &step, &rss),
                 0);
    cr_assert_str_eq(t.id, "12_3");
    cr_assert(step);
    cr_assert_float_eq(rss, 2.0, 1e-12);
    cr_assert_float_eq(t.elapsed_s, 65.0, 1e-9);
    cr_assert_eq(slurm_parse_sacct("12_4|CANCELLED by 0|0:15|00:00:07|node2|Unknown|Unknown|",
                                   &t, &step, &rss),
                 0);
    cr_assert(!step);
    cr_assert_str_eq(t.state, "CANCELLED");
    cr_assert(WIFSIGNALED(t.exit_status) && WTERMSIG(t.exit_status) == 15);
    cr_assert_float_eq(rss, 0.0, 0.0);
    cr_assert_eq(slurm_parse_sacct("12_5|FAILED|3:0|1-00:00:01|n|x|y|1.5G", &t, &step, &rss), 0);
    cr_assert(WIFEXITED(t.exit_status) && WEXITSTATUS(t.exit_status) == 3);
    cr_assert_float_eq(rss, 1536.0, 1e-9);
    cr_assert_float_eq(t.elapsed_s, 86401.0, 1e-9);

    /* the mapping, on an empty run directory */
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    struct {
        const char *state;
        int ws;
        enum run_status want;
        enum failure_class fc;
    } cases[] = {
        {"FAILED", 3 << 8, RS_FAILED, FC_JOB},         {"FAILED", 11, RS_CRASHED, FC_JOB},
        {"OUT_OF_MEMORY", 9, RS_FAILED, FC_JOB},       {"TIMEOUT", 15, RS_TIMEOUT, FC_JOB},
        {"NODE_FAIL", 0, RS_CANCELLED, FC_INFRA},      {"PREEMPTED", 0, RS_CANCELLED, FC_INFRA},
        {"BOOT_FAIL", 0, RS_CANCELLED, FC_INFRA},      {"CANCELLED", 15, RS_CANCELLED, FC_NONE},
        {"COMPLETED", 0, RS_FAILED, FC_JOB},   /* exit 0 but no result.json */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        memset(&t, 0, sizeof t);
        snprintf(t.state, sizeof t.state, "%s", cases[i].state);
        t.exit_status = cases[i].ws;
        struct outcome o;
        slurm_outcome(&o, &t, dir, 0, "0-00:01:00");
        cr_assert_eq(o.status, cases[i].want, "%s: status %s", cases[i].state,
                     run_status_name(o.status));
        cr_assert_eq(o.failure, cases[i].fc, "%s: failure class", cases[i].state);
        cr_assert_str_eq(o.slurm_state, cases[i].state);
        outcome_free(&o);
    }
    ct_rmrf(dir);
}

/* The lines are what squeue printed for tasks of a 1000-job sweep cancelled
 * while their batch scripts were being launched (make bench, 2026-11-27):
 * the launch failed after the cancel, Slurm requeued and held them, and the
 * runner waited for them for ever. */
Test(campaign_slurm, held_and_recancelled_tasks)
{
    struct slurm_task t;
    cr_assert_eq(slurm_parse_task("105_176|PENDING|0|0:00|N/A|N/A|launch failed requeued held|", &t),
                 0);
    cr_assert_str_eq(t.reason, "launch failed requeued held");
    /* not cancelled by us: Slurm's hold is an infrastructure failure */
    cr_assert_eq(slurm_queued_action(&t, 0), SQ_LAUNCH_FAILED);
    /* cancelled by us and pending again: cancel it again */
    cr_assert_eq(slurm_queued_action(&t, 1), SQ_CANCEL_AGAIN);
    /* scontrol's spelling of the same reason */
    snprintf(t.reason, sizeof t.reason, "launch_failed_requeued_held");
    cr_assert_eq(slurm_queued_action(&t, 0), SQ_LAUNCH_FAILED);
    /* an ordinary pending task, one an administrator holds, a running one */
    const char *wait_reasons[] = {"Resources", "Priority", "JobArrayTaskLimit", "JobHeldAdmin",
                                  "JobHeldUser", "launch failed requeued", ""};
    for (size_t i = 0; i < sizeof wait_reasons / sizeof wait_reasons[0]; i++) {
        snprintf(t.reason, sizeof t.reason, "%s", wait_reasons[i]);
        cr_assert_eq(slurm_queued_action(&t, 0), SQ_WAIT, "reason '%s'", wait_reasons[i]);
    }
    snprintf(t.state, sizeof t.state, "RUNNING");
    snprintf(t.reason, sizeof t.reason, "None");
    cr_assert_eq(slurm_queued_action(&t, 0), SQ_WAIT);
    cr_assert_eq(slurm_queued_action(&t, 1), SQ_WAIT);   /* ending: no second scancel */
    snprintf(t.state, sizeof t.state, "REQUEUE_HOLD");
    cr_assert_eq(slurm_queued_action(&t, 1), SQ_CANCEL_AGAIN);
}

Test(campaign_slurm, extra_options)
{
    char why[512];
    cr_assert(slurm_extra_ok("--exclusive", why, sizeof why));
    cr_assert(slurm_extra_ok("--gres=gpu:2", why, sizeof why));
    const char *bad[] = {"-J x", "--array=0-9", "--wrap=rm", "--output=/tmp/x", "--mem=1G\n#SBATCH",
                         "--comment=a b", "--comment=$(id)", "--comment='x'", "--x;y", NULL};
    for (int i = 0; bad[i]; i++)
        cr_assert(!slurm_extra_ok(bad[i], why, sizeof why), "'%s' accepted", bad[i]);
}

/* Hostile values in a study: each is refused with the file, line and key,
 * before anything runs. */
Test(campaign_slurm, hostile_values_are_refused)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    struct {
        const char *yaml, *key;
    } cases[] = {
        {"slurm: {partition: \"a\\n#SBATCH --wrap=reboot\"}\n", "slurm.partition"},
        {"slurm: {account: \"x; rm -rf /\"}\n", "slurm.account"},
        {"slurm: {qos: \"$(reboot)\"}\n", "slurm.qos"},
        {"slurm: {time: \"1:00\\n#SBATCH --uid=0\"}\n", "slurm.time"},
        {"slurm: {mem: \"4G --wrap=x\"}\n", "slurm.mem"},
        {"slurm: {constraint: \"a b\"}\n", "slurm.constraint"},
        {"slurm: {extra: [\"--comment=`id`\"]}\n", "slurm.extra[0]"},
        {"slurm: {extra: [\"--array=0-99\"]}\n", "slurm.extra[0]"},
        {"slurm: {extra: [\"--mem=1G\\n#SBATCH --wrap=x\"]}\n", "slurm.extra[0]"},
        {"slurm: {ntasks: \"4; reboot\"}\n", "slurm.ntasks"},
        {"slurm: {time: {by: fake.x, values: [\"00:10:00\", \"'; reboot\"]}}\n",
         "slurm.time.values[1]"},
        {"slurm: {time: {by: fake.y, values: [1, 2]}}\n", "slurm.time.by"},
        {"slurm: {time: {by: fake.x, values: [1]}}\n", "slurm.time.values"},
        {"slurm: {partitoin: x}\n", "slurm.partitoin"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char study[1024];
        snprintf(study, sizeof study,
                 "name: hostile\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: [1, 2]}}\n"
                 "backend: slurm\n%s",
                 cases[i].yaml);
        ct_write(0, dir, "h.yaml", study);
        int rc = ct_cascade(dir, NULL, out, sizeof out, "plan", "h.yaml", "--solver",
                            ct_standin(), NULL);
        cr_assert_eq(rc, 2, "case %zu: exit %d: %s", i, rc, out);
        char want[128];
        snprintf(want, sizeof want, "h.yaml:5:");
        cr_assert(strstr(out, want) && strstr(out, cases[i].key), "case %zu: %s", i, out);
    }
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    cr_assert_neq(access(path, F_OK), 0, "a database was written");
    ct_rmrf(dir);
}

/* The job script runs exactly the argument vector, whatever the words hold. */
Test(campaign_slurm, job_script_quotes_every_word)
{
    char dir[64], cwd[256], pwned[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(cwd, sizeof cwd, "%s/it's a $(dir) `x`", dir);
    mkdir(cwd, 0755);
    snprintf(pwned, sizeof pwned, "%s/pwned", dir);
    char cmdsub[256];
    snprintf(cmdsub, sizeof cmdsub, "$(touch %s)", pwned);
    struct launch_spec L;
    memset(&L, 0, sizeof L);
    snprintf(L.run_dir, sizeof L.run_dir, "%s/run", dir);
    mkdir(L.run_dir, 0755);
    snprintf(L.cwd, sizeof L.cwd, "%s", cwd);
    char *argv[] = {"/usr/bin/printf", "[%s]\\n", "a'b", cmdsub, "x\ny", "#SBATCH --wrap=x",
                    "; echo hi", NULL};
    L.argv = argv;
    L.argc = 7;
    struct slurm_spec sp;
    memset(&sp, 0, sizeof sp);
    struct slurm_job_res jr;
    memset(&jr, 0, sizeof jr);
    snprintf(jr.v[SR_TIME], sizeof jr.v[SR_TIME], "0-00:01:00");
    jr.ntasks = 1;
    struct slurm_job_script js = {"s", "k", "cascade.s", 1, &L, &jr, &sp};
    char script[256];
    snprintf(script, sizeof script, "%s/job.sbatch", L.run_dir);
    struct err e = {0};
    cr_assert_eq(slurm_write_job_script(script, &js, &e), 0, "%s", e.msg);
    const char *bash[] = {"/bin/bash", script, NULL};
    char out[1024];
    cr_assert_eq(ct_exec(dir, NULL, bash, out, sizeof out), 0, "%s", out);
    char so[256], got[1024] = "";
    snprintf(so, sizeof so, "%s/stdout", L.run_dir);
    FILE *f = fopen(so, "r");
    cr_assert_not_null(f);
    size_t n = fread(got, 1, sizeof got - 1, f);
    got[n] = '\0';
    fclose(f);
    char want[1024];
    snprintf(want, sizeof want, "[a'b]\n[%s]\n[x\ny]\n[#SBATCH --wrap=x]\n[; echo hi]\n", cmdsub);
    cr_assert_str_eq(got, want);
    cr_assert_neq(access(pwned, F_OK), 0, "a word was run by the shell");
    /* a run directory an #SBATCH line cannot carry is refused */
    snprintf(L.run_dir, sizeof L.run_dir, "%s/bad dir", dir);
    cr_assert_neq(slurm_write_job_script(script, &js, &e), 0);
    ct_rmrf(dir);
}

/* --- against the cluster ---------------------------------------------------- */

#define NSAME 20

/* job key -> "status metric=value ..." of a database, sorted, one line per job */
static void rows_of(const char *dir, char *out, size_t len)
{
    sqlite3 *db = ct_db(dir);
    sqlite3_stmt *st;
    cr_assert_eq(sqlite3_prepare_v2(
                     db,
                     "SELECT j.key || ' ' || j.state || ' ' || r.status || ' ' || r.attempt || ' ' "
                     "|| coalesce(r.exit_code, '-') || ' ' || coalesce((SELECT group_concat(name "
                     "|| '=' || printf('%.17g', value), ',') FROM (SELECT * FROM metrics m WHERE "
                     "m.run_id = r.id ORDER BY name)), '') FROM jobs j JOIN runs r ON r.job_id = "
                     "j.id ORDER BY j.key, r.attempt",
                     -1, &st, NULL),
                 SQLITE_OK);
    out[0] = '\0';
    while (sqlite3_step(st) == SQLITE_ROW)
        snprintf(out + strlen(out), len - strlen(out), "%s\n", sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    sqlite3_close(db);
}

Test(campaign_slurm, twenty_jobs_same_rows_as_local, .fini = stop_cluster, .timeout = 240)
{
    start_cluster(NULL);
    char local[64], slurm[64], out[16384];
    ct_mkdir(local, sizeof local);
    ct_mkdir(slurm, sizeof slurm);
    char study[1024] = "name: same\nbase: {fake: {action: ok, y: 0.5}}\n"
                       "sweep: {grid: {fake.x: [";
    for (int i = 0; i < NSAME; i++)
        snprintf(study + strlen(study), sizeof study - strlen(study), "%s%d.25", i ? ", " : "",
                 i);
    snprintf(study + strlen(study), sizeof study - strlen(study),
             "]}}\nslurm: {poll: 0.3, time: 2}\n");
    ct_write(0, local, "s.yaml", study);
    ct_write(1, slurm, "s.yaml", study);
    int rc = ct_cascade(local, NULL, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    const char *env[] = {wrap_sbatch(slurm), NULL};
    rc = ct_cascade(slurm, env, out, sizeof out, "run", "s.yaml", "--backend", "slurm",
                    "--solver", ct_standin(), "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    char a[16384], b[16384];
    rows_of(local, a, sizeof a);
    rows_of(slurm, b, sizeof b);
    cr_assert_eq(count_lines(a), NSAME);
    cr_assert_str_eq(a, b);
    sqlite3 *db = ct_db(slurm);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE slurm_job_id LIKE '%\\_%' ESCAPE '\\' "
                            "AND slurm_state = 'COMPLETED' AND launcher = 'slurm'"),
                 NSAME);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT slurm_job_id) FROM runs"), NSAME);
    sqlite3_close(db);
    /* one group of resources, 20 < MaxArraySize: one array */
    cr_assert_eq(submissions(slurm), 1);
    ct_rmrf(local);
    ct_rmrf(slurm);
}

Test(campaign_slurm, max_array_size_splits_the_sweep, .fini = stop_cluster, .timeout = 180)
{
    struct slurmfx_opts o = {0, 5, NULL};
    start_cluster(&o);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: split\nbase: {fake: {action: ok}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}}\n"
             "backend: slurm\nslurm: {poll: 0.3, time: 2}\n");
    const char *env[] = {wrap_sbatch(dir), NULL};
    int rc = ct_cascade(dir, env, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_eq(submissions(dir), 3);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT substr(slurm_job_id, 1, "
                            "instr(slurm_job_id, '_') - 1)) FROM runs"),
                 3);
    cr_assert_eq(ct_int(db, "SELECT max(n) FROM (SELECT count(*) AS n FROM runs GROUP BY "
                            "substr(slurm_job_id, 1, instr(slurm_job_id, '_') - 1))"),
                 5);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 12);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_slurm, throttle_two_never_runs_three, .fini = stop_cluster, .timeout = 180)
{
    start_cluster(NULL);
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: thr\nbase: {fake: {action: sleep, seconds: 2}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6]}}\n"
             "backend: slurm\nmax_running: 2\nslurm: {poll: 0.3, time: 2}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(), "--quiet",
                          NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "run.log");
    int most = 0, samples = 0, status = -1;
    for (int i = 0; i < 1200; i++) {
        char q[4096] = "";
        const char *sq[] = {"squeue", "-h", "-r", "-t", "RUNNING", "--name=cascade.thr", "-o",
                            "%i", NULL};
        if (slurmfx_client(sq, q, sizeof q) == 0) {
            int n = count_lines(q);
            most = n > most ? n : most;
            samples++;
        }
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            break;
        }
        usleep(100000);
    }
    cr_assert_eq(status, 0, "runner exit %d", status);
    cr_assert_gt(samples, 20);
    cr_assert_leq(most, 2, "%d jobs ran at once with max_running 2", most);
    cr_assert_eq(most, 2, "never 2 at once: the node (8 CPUs) should have allowed it");
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 6);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_slurm, bad_resources_fail_before_submitting, .fini = stop_cluster, .timeout = 120)
{
    start_cluster(NULL);
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    const char *env[] = {wrap_sbatch(dir), NULL};
    ct_write(0, dir, "p.yaml",
             "name: badp\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: [1, 2]}}\n"
             "backend: slurm\n"
             "slurm: {partition: nope}\n");
    int rc = ct_cascade(dir, env, out, sizeof out, "run", "p.yaml", "--solver", ct_standin(),
                        NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "p.yaml:5:") && strstr(out, "slurm.partition") &&
                  strstr(out, "'nope' is not a partition of this cluster (it has: test)"),
              "%s", out);
    /* the time limit grows with the swept key; the second job's is over the partition's */
    ct_write(1, dir, "t.yaml",
             "name: badt\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: [1, 2]}}\n"
             "backend: slurm\n"
             "slurm:\n  time: {by: fake.x, values: [\"00:05:00\", \"00:20:00\"]}\n");
    rc = ct_cascade(dir, env, out, sizeof out, "run", "t.yaml", "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "t.yaml:6:") && strstr(out, "slurm.time") &&
                  strstr(out, "0-00:20:00 (job fake.x=2) is over the MaxTime of partition test"),
              "%s", out);
    cr_assert_eq(submissions(dir), 0, "something was submitted");
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    cr_assert_neq(access(path, F_OK), 0, "a database was written");
    snprintf(path, sizeof path, "%s/runs", dir);
    cr_assert_neq(access(path, F_OK), 0, "run directories were written");
    ct_rmrf(dir);
}

static long long db_count(const char *dir, const char *sql)
{
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    if (access(path, F_OK) != 0)
        return -1;
    sqlite3 *db = ct_db(dir);
    sqlite3_stmt *st;
    long long got = -1;
    if (sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK) {
        if (sqlite3_step(st) == SQLITE_ROW)
            got = sqlite3_column_int64(st, 0);
        sqlite3_finalize(st);
    }
    sqlite3_close(db);
    return got;
}

Test(campaign_slurm, kill9_runner_then_run_again_adopts, .fini = stop_cluster, .timeout = 240)
{
    start_cluster(NULL);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: adopt\nbase: {fake: {action: sleep, seconds: 3}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8]}}\n"
             "backend: slurm\nmax_running: 3\nslurm: {poll: 0.3, time: 2}\n");
    const char *env[] = {wrap_sbatch(dir), NULL};
    const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(), "--quiet",
                          "--lease", "5", NULL};
    pid_t pid = ct_spawn(dir, env, argv, "run1.log");
    /* every job submitted and some running: then the runner dies */
    int ready = 0;
    for (int i = 0; i < 600 && !ready; i++) {
        usleep(100000);
        char q[4096] = "";
        const char *sq[] = {"squeue", "-h", "-r", "-t", "RUNNING", "--name=cascade.adopt", "-o",
                            "%i", NULL};
        ready = db_count(dir, "SELECT count(*) FROM runs WHERE slurm_job_id IS NOT NULL") == 8 &&
                slurmfx_client(sq, q, sizeof q) == 0 && count_lines(q) >= 1;
    }
    cr_assert(ready, "the jobs were not submitted and running within 60 s");
    kill(pid, SIGKILL);
    cr_assert_eq(ct_wait(pid), 128 + SIGKILL);
    cr_assert_gt(db_count(dir, "SELECT count(*) FROM runs WHERE status = 'running'"), 0);
    /* status says so from the database */
    int rc = ct_cascade(dir, NULL, out, sizeof out, "status", "adopt", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strstr(out, "in Slurm: ") && strstr(out, "with no runner following"), "%s", out);
    rc = ct_cascade(dir, env, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                    "--lease", "5", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strstr(out, "already in Slurm"), "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 8, "a job ran twice");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done' AND attempt = 1"), 8);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    cr_assert_eq(submissions(dir), 1, "submitted again after the runner died");
    /* and Slurm saw each job once */
    char q[8192] = "";
    const char *sq[] = {"squeue", "-h", "-r", "--states=all", "--name=cascade.adopt", "-o", "%i",
                        NULL};
    cr_assert_eq(slurmfx_client(sq, q, sizeof q), 0);
    cr_assert_eq(count_lines(q), 8, "%s", q);
    ct_rmrf(dir);
}

Test(campaign_slurm, cancel_stops_queued_and_running, .fini = stop_cluster, .timeout = 180)
{
    start_cluster(NULL);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: cnl\nbase: {fake: {action: sleep, seconds: 60}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n"
             "backend: slurm\nmax_running: 2\nslurm: {poll: 0.3, time: 3}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(), "--quiet",
                          NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "run.log");
    int ready = 0;
    for (int i = 0; i < 600 && !ready; i++) {
        usleep(100000);
        char q[4096] = "";
        const char *sq[] = {"squeue", "-h", "-r", "-t", "RUNNING", "--name=cascade.cnl", "-o",
                            "%i", NULL};
        ready = db_count(dir, "SELECT count(*) FROM runs WHERE slurm_job_id IS NOT NULL") == 4 &&
                slurmfx_client(sq, q, sizeof q) == 0 && count_lines(q) == 2;
    }
    cr_assert(ready, "not 2 running and 2 queued within 60 s");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "cancel", "cnl", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strstr(out, "cancelled 4 Slurm jobs"), "%s", out);
    int st = ct_wait(pid);
    cr_assert_neq(st, 0);
    char q[4096] = "x";
    const char *sq[] = {"squeue", "-h", "-r", "-t", "PENDING,RUNNING", "--name=cascade.cnl", "-o",
                        "%i", NULL};
    for (int i = 0; i < 50 && q[0]; i++) {
        q[0] = '\0';
        slurmfx_client(sq, q, sizeof q);
        if (q[0])
            usleep(100000);
    }
    cr_assert_str_eq(q, "", "still in the queue: %s", q);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled'"), 4);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'running'"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* Slurm ends the first attempt at its time limit (one minute, enforced
 * within Slurm's 30 s check: 60-90 s); the job had written checkpoints, so
 * the retry continues from the newest (the stand-in's `steps` action). */
Test(campaign_slurm, timeout_resumes_from_the_checkpoint, .fini = stop_cluster, .timeout = 300)
{
    start_cluster(NULL);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: tmo\n"
             "base: {fake: {action: steps, steps: 200, step_seconds: 0.5, checkpoint_every: 4}}\n"
             "sweep: {grid: {fake.x: [1]}}\n"
             "backend: slurm\nretries: 1\nslurm: {poll: 0.5, time: 1}\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    char s[64], msg[512];
    ct_text(db, "SELECT status FROM runs WHERE attempt = 1", s, sizeof s);
    cr_assert_str_eq(s, "timeout");
    ct_text(db, "SELECT slurm_state FROM runs WHERE attempt = 1", s, sizeof s);
    cr_assert_str_eq(s, "TIMEOUT");
    ct_text(db, "SELECT message FROM runs WHERE attempt = 1", msg, sizeof msg);
    cr_assert(strstr(msg, "time limit of 0-00:01:00"), "%s", msg);
    ct_text(db, "SELECT status FROM runs WHERE attempt = 2", s, sizeof s);
    cr_assert_str_eq(s, "done");
    long long from = ct_int(db, "SELECT resumed_from_step FROM runs WHERE attempt = 2");
    /* killed 60-90 s into 0.5 s steps, checkpoints every 4 steps */
    cr_assert(from >= 100 && from <= 200 && from % 4 == 0, "resumed from step %lld", from);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE attempt = 1 AND resumed_from_step "
                            "IS NOT NULL"),
                 0);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* A hang-up (logged out) leaves the jobs in Slurm; a local runner refuses
 * to run them a second time; the next Slurm runner adopts them. */
Test(campaign_slurm, hangup_leaves_jobs_in_slurm, .fini = stop_cluster, .timeout = 180)
{
    start_cluster(NULL);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: hup\nbase: {fake: {action: sleep, seconds: 2}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n"
             "backend: slurm\nmax_running: 2\nslurm: {poll: 0.3, time: 2}\n");
    const char *env[] = {wrap_sbatch(dir), NULL};
    const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(), NULL};
    pid_t pid = ct_spawn(dir, env, argv, "run1.log");
    for (int i = 0; i < 600; i++) {
        usleep(100000);
        if (db_count(dir, "SELECT count(*) FROM runs WHERE slurm_job_id IS NOT NULL") == 4)
            break;
    }
    kill(pid, SIGHUP);
    cr_assert_eq(ct_wait(pid), 128 + SIGHUP);
    long long left = db_count(dir, "SELECT count(*) FROM runs WHERE status = 'running'");
    cr_assert_gt(left, 0, "nothing left in Slurm to adopt");
    cr_assert_eq(db_count(dir, "SELECT count(*) FROM runs WHERE status = 'cancelled'"), 0);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--backend", "local",
                        "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "in Slurm with no runner following them"), "%s", out);
    rc = ct_cascade(dir, env, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(), NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 4);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 4);
    sqlite3_close(db);
    cr_assert_eq(submissions(dir), 1);
    ct_rmrf(dir);
}

/* ntasks > 1: the job script starts the solver through srun, on that many
 * tasks (each copy of the stand-in says so on stderr). */
Test(campaign_slurm, ntasks_runs_the_solver_through_srun, .fini = stop_cluster, .timeout = 120)
{
    start_cluster(NULL);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: mpi\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: [3]}}\n"
             "backend: slurm\nslurm: {poll: 0.3, time: 2, ntasks: 2, mem: 200M}\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    char rd[512], path[600], text[8192];
    ct_text(db, "SELECT run_dir FROM runs", rd, sizeof rd);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 1);
    sqlite3_close(db);
    snprintf(path, sizeof path, "%s/job.sbatch", rd);
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s", path);
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    cr_assert(strstr(text, "\n#SBATCH --ntasks=2\n") && strstr(text, "\n#SBATCH --mem=200M\n") &&
                  strstr(text, "\nexec srun --ntasks=2 --cpus-per-task=1 '"),
              "%s", text);
    snprintf(path, sizeof path, "%s/stderr", rd);
    f = fopen(path, "r");
    cr_assert_not_null(f);
    n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    int copies = 0;
    for (const char *p = text; (p = strstr(p, "action ok")); p++)
        copies++;
    cr_assert_eq(copies, 2, "%s", text);
    ct_rmrf(dir);
}

/* slurm.max_submit (as MaxSubmitJobs would): never more of the study's
 * jobs in the queue than that, the rest submitted as earlier ones end. */
Test(campaign_slurm, max_submit_bounds_the_queue, .fini = stop_cluster, .timeout = 180)
{
    start_cluster(NULL);
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: msub\nbase: {fake: {action: sleep, seconds: 1}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9]}}\n"
             "backend: slurm\nslurm: {poll: 0.3, time: 2, max_submit: 3}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(), "--quiet",
                          NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "run.log");
    int most = 0, status = -1;
    for (int i = 0; i < 1200; i++) {
        char q[4096] = "";
        const char *sq[] = {"squeue", "-h", "-r", "-t", "PENDING,RUNNING,CONFIGURING",
                            "--name=cascade.msub", "-o", "%i", NULL};
        if (slurmfx_client(sq, q, sizeof q) == 0 && count_lines(q) > most)
            most = count_lines(q);
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            break;
        }
        usleep(100000);
    }
    cr_assert_eq(status, 0);
    cr_assert_leq(most, 3, "%d of the study's jobs in the queue at once", most);
    cr_assert_geq(most, 2);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 9);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 9);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* cascade cancel with the runner gone: the attempts are cancelled in Slurm
 * and recorded as cancelled by cascade cancel itself. */
Test(campaign_slurm, cancel_with_the_runner_gone, .fini = stop_cluster, .timeout = 120)
{
    start_cluster(NULL);
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: gone\nbase: {fake: {action: sleep, seconds: 60}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3]}}\n"
             "backend: slurm\nmax_running: 1\nslurm: {poll: 0.3, time: 3}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(), "--quiet",
                          NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "run.log");
    for (int i = 0; i < 600; i++) {
        usleep(100000);
        if (db_count(dir, "SELECT count(*) FROM runs WHERE slurm_job_id IS NOT NULL") == 3)
            break;
    }
    kill(pid, SIGKILL);
    cr_assert_eq(ct_wait(pid), 128 + SIGKILL);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "cancel", "gone", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strstr(out, "cancelled 3 Slurm jobs (0 followed by a live runner"), "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled' AND "
                            "message = 'cancelled by cascade cancel' AND slurm_state = "
                            "'CANCELLED' AND failure_class IS NULL"),
                 3);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    char q[4096] = "x";
    const char *sq[] = {"squeue", "-h", "-r", "-t", "PENDING,RUNNING,COMPLETING",
                        "--name=cascade.gone", "-o", "%i", NULL};
    for (int i = 0; i < 50 && q[0]; i++) {
        q[0] = '\0';
        slurmfx_client(sq, q, sizeof q);
        if (q[0])
            usleep(100000);
    }
    cr_assert_str_eq(q, "", "still in the queue: %s", q);
    /* nothing left to cancel */
    rc = ct_cascade(dir, NULL, out, sizeof out, "cancel", "gone", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strstr(out, "nothing queued or running in Slurm"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "cancel", "nosuch", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    ct_rmrf(dir);
}
