/*
 * fuzz_corpus: every input of the fuzz corpora (tests/fuzz/corpus/<reader>/)
 * and every input that once crashed a reader (tests/fuzz/crashes/<reader>/)
 * goes through the same harness as `make fuzz` uses (fuzz/fuzz_<reader>.c).
 * The harness aborts on a reader failure without a message and on broken
 * invariants; under `make test SANITIZE=1` any ASan/UBSan report fails the
 * test too.  No fuzzing happens here, only the replay.
 */
#include <criterion/criterion.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "campaign/outcome.h"
#include "core/ghost.h"
#include "campaign/study.h"
#include "fuzz/fuzz.h"
#include "helpers/th.h"
#include "input/case.h"
#include "input/config_read.h"

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static unsigned char *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "cannot open %s", path);
    size_t cap = 4096, n = 0, got;
    unsigned char *buf = malloc(cap);
    cr_assert_not_null(buf);
    while ((got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap);
            cr_assert_not_null(buf);
        }
    }
    fclose(f);
    *size = n;
    return buf;
}

/* Run every regular file of dir through fn; returns how many there were. */
static int replay_dir(const char *dir, int (*fn)(const uint8_t *, size_t))
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    char **names = NULL;
    int n = 0;
    struct dirent *de;
    while ((de = readdir(d))) {
        if (de->d_name[0] == '.')
            continue;
        names = realloc(names, (size_t)(n + 1) * sizeof *names);
        cr_assert_not_null(names);
        names[n++] = strdup(de->d_name);
    }
    closedir(d);
    if (n)
        qsort(names, (size_t)n, sizeof *names, cmp_str);
    for (int i = 0; i < n; i++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        size_t size;
        unsigned char *data = slurp(path, &size);
        /* a crash names the input through Criterion's log of the last file */
        cr_log_info("%s", path);
        cr_assert_eq(fn(data, size), 0, "%s", path);
        free(data);
        free(names[i]);
    }
    free(names);
    return n;
}

static void replay(const char *reader, int (*fn)(const uint8_t *, size_t))
{
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/tests/fuzz/corpus/%s", th_root(), reader);
    int n = replay_dir(dir, fn);
    cr_assert_gt(n, 0, "no corpus in %s", dir);
    snprintf(dir, sizeof dir, "%s/tests/fuzz/crashes/%s", th_root(), reader);
    replay_dir(dir, fn);
}

Test(fuzz_corpus, case_yaml) { replay("case", fuzz_case_one); }
Test(fuzz_corpus, study_yaml) { replay("study", fuzz_study_one); }
Test(fuzz_corpus, lammps_data) { replay("lammps_data", fuzz_lammps_data_one); }
Test(fuzz_corpus, extxyz) { replay("extxyz", fuzz_extxyz_one); }
Test(fuzz_corpus, eam) { replay("eam", fuzz_eam_one); }
Test(fuzz_corpus, stillinger_weber) { replay("sw", fuzz_sw_one); }
Test(fuzz_corpus, meam_spline) { replay("meam_spline", fuzz_meam_spline_one); }
Test(fuzz_corpus, result_json) { replay("result_json", fuzz_result_json_one); }
Test(fuzz_corpus, baseline) { replay("baseline", fuzz_baseline_one); }

/* --- what the fixes of crashes found by fuzzing now say ---------------------- */

static void read_xyz(const char *crash, int *rc, char *msg, size_t len)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/tests/fuzz/crashes/extxyz/%s", th_root(), crash);
    struct particles *p = particles_create(8);
    struct box b = {0};
    int pbc[3];
    struct err e = {0};
    *rc = config_read_extxyz(path, NULL, p, &b, pbc, &e);
    snprintf(msg, len, "%s", e.msg);
    particles_destroy(&p);
}

Test(fuzz_corpus, extxyz_property_columns_inside_the_line)
{
    int rc;
    char msg[ERR_MSG_MAX];
    /* vel:R:1 as the 63rd column: vel was read from columns 63 to 65 */
    read_xyz("crash-vel-column-64", &rc, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "crash-vel-column-64:2: Properties: vel must be vel:R:3, found vel:R:1"),
              "%s", msg);
    /* vel:R:0 on a 4-column line: vel was read past the end of the line */
    read_xyz("crash-vel-count-0", &rc, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "malformed Properties at 'vel'"), "%s", msg);
}

Test(fuzz_corpus, study_set_with_a_bad_key_path)
{
    /* the message was formatted from the freed settings (heap-use-after-free) */
    char path[4096];
    snprintf(path, sizeof path, "%s/tests/fuzz/crashes/study/crash-set-bad-key-path", th_root());
    size_t size;
    unsigned char *text = slurp(path, &size);
    text = realloc(text, size + 1);
    text[size] = '\0';
    th_write_temp(0, "case.yaml", "system: {lattice: {style: fcc, a: 3.6}, element: Cu}\n");
    const char *study = th_write_temp(1, "study.yaml", (const char *)text);
    free(text);
    struct study s;
    struct err e = {0};
    cr_assert_eq(study_load(&s, study, &e), ERR_INPUT);
    cr_assert(strstr(e.msg, "study.yaml:3:7: set.$a: '$a' is not a case key path"), "%s", e.msg);
}

Test(fuzz_corpus, study_report_order_null)
{
    /* cfg_real deleted the null entry while read_order iterated over the
     * mapping, then named the freed key in its message (heap-use-after-free) */
    th_write_temp(0, "case.yaml", "system: {lattice: {style: fcc, a: 3.6}, element: Cu}\n");
    const char *study = th_write_temp(1, "study.yaml", "name: x\nbase: case.yaml\nreport:\n"
                                                       "  order: {default: 2, pe: ~}\n");
    struct study s;
    struct err e = {0};
    cr_assert_eq(study_load(&s, study, &e), ERR_INPUT);
    cr_assert(strstr(e.msg, "study.yaml:4:27: report.order.pe: must be a number, found null"),
              "%s", e.msg);
}

Test(fuzz_corpus, outcome_message_cut_inside_a_character)
{
    /* result.json's message is cut to the outcome's 1023 bytes inside the
     * 'Å' after 1022 'a': outcome_to_json returned NULL, so an MPI worker
     * sent "{}" and rank 0 recorded "bad result message" instead */
    char src[4096];
    snprintf(src, sizeof src, "%s/tests/fuzz/crashes/result_json/crash-message-cut-in-utf8",
             th_root());
    size_t size;
    unsigned char *text = slurp(src, &size);
    text = realloc(text, size + 1);
    text[size] = '\0';
    const char *path = th_write_temp(0, "result.json", (const char *)text);
    free(text);
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    *strrchr(dir, '/') = '\0';
    struct outcome o;
    memset(&o, 0, sizeof o);
    struct exit_info x = {4 << 8, 0, 0, 0.0, 0};
    outcome_collect(&o, dir, &x);
    cr_assert_eq(o.status, RS_DIVERGED);
    cr_assert_eq(strlen(o.message), OUTCOME_MSG_MAX - 1);
    json_t *j = outcome_to_json(&o);
    cr_assert_not_null(j, "the outcome must go into the worker's message");
    struct outcome back;
    struct err e = {0};
    cr_assert_eq(outcome_from_json(&back, j, &e), 0, "%s", e.msg);
    cr_assert_eq(back.status, RS_DIVERGED);
    char want[OUTCOME_MSG_MAX];
    memset(want, 'a', OUTCOME_MSG_MAX - 2);
    want[OUTCOME_MSG_MAX - 2] = '?';
    want[OUTCOME_MSG_MAX - 1] = '\0';
    cr_assert_str_eq(back.message, want);
    json_decref(j);
    outcome_free(&back);
    outcome_free(&o);
}

Test(fuzz_corpus, periodic_box_far_below_the_range)
{
    /* a LAMMPS data file that reads (lo < hi) with a box of 1e-300 Å: the
     * run's ghost build cast 1.2e301 image layers to int (UBSan:
     * float-cast-overflow); now an input error */
    struct particles *p = particles_create(8);
    particles_add(p, (double[]){0, 5, 5}, NULL, particles_type_index(p, "Cu", 63.546), 1);
    struct box b = {{0, 0, 0}, {1e-300, 10, 10}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC,
                                                  BOUNDARY_PERIODIC}, {0, 0, 0}};
    struct err e = {0};
    cr_assert_eq(ghost_build(p, &b, 11.83, &e), ERR_INPUT);
    /* either guard may answer first: the estimate of the images, or the
     * layer count of the axis */
    cr_assert(strstr(e.msg, "1e-300") && strstr(e.msg, "11.83 Å"), "%s", e.msg);
    /* a box shorter than the range still gets its image layers: 3 along x */
    b.hi[0] = 5.0;
    cr_assert_eq(ghost_build(p, &b, 11.83, &e), 0, "%s", e.msg);
    int maxshift = 0;
    for (int g = p->n_owned; g < p->n_owned + p->n_ghost; g++)
        if (p->gshift[3 * g] > maxshift)
            maxshift = p->gshift[3 * g];
    cr_assert_eq(maxshift, 3);
    particles_destroy(&p);
}

Test(fuzz_corpus, mpm_report_step_beyond_long)
{
    /* report_steps: [..., 1.03e67, ...] was converted to long (UBSan:
     * float-cast-overflow); now refused at the key */
    char path[4096];
    snprintf(path, sizeof path, "%s/tests/fuzz/crashes/case/crash-mpm-report-step-1e67",
             th_root());
    struct case_doc cd;
    struct case_resolved cr;
    struct err e = {0};
    int rc = case_load_file(&cd, path, &e);
    cr_assert_eq(rc, 0, "%s", e.msg);
    rc = case_resolve(&cd, 0, 1, NULL, &cr, &e);
    if (!rc)
        case_resolved_free(&cr);
    case_doc_free(&cd);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(e.msg, "crash-mpm-report-step-1e67:28:17:") &&
                  strstr(e.msg, "mpm.report_steps: steps must be integers from 0 to 1e15"),
              "%s", e.msg);
}
