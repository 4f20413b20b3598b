/*
 * Studies: expansion counts (grid x zip x repeats, preparation jobs), key
 * stability (the same study written with its keys in another order gives
 * the same job keys; keys are the solver's), the values put into each case,
 * and the bad-input messages -- each naming the study file, line and
 * column -- with nothing written to the database on bad input.
 */
#include <criterion/criterion.h>
#include <string.h>
#include <unistd.h>

#include "../campaign/plan.h"
#include "helpers/ct.h"
#include "helpers/th.h"

#define CRYSTAL                                                                                   \
    "base:\n"                                                                                     \
    "  type: crystal\n"                                                                           \
    "  crystal: {lattice: fcc, element: Cu, a_min: 3.4, a_max: 3.8}\n"                            \
    "  potential: {style: sutton_chen}\n"

struct loaded {
    struct study s;
    struct solver sv;
    struct plan p;
};

/* Load and expand with the real solver; returns the error class. */
static int expand(const char *dir, const char *text, struct loaded *L, char *msg, size_t len)
{
    const char *path = ct_write(0, dir, "study.yaml", text);
    struct err e = {0};
    int rc = study_load(&L->s, path, &e);
    if (!rc) {
        rc = solver_open(&L->sv, th_solver(), &e);
        if (!rc)
            rc = plan_build(&L->p, &L->s, &L->sv, &e);
        if (rc)
            study_free(&L->s);
    }
    snprintf(msg, len, "%s", e.msg);
    return rc;
}

static void unload(struct loaded *L)
{
    plan_free(&L->p);
    study_free(&L->s);
}

Test(campaign_study, expansion_counts_and_values)
{
    char dir[64], msg[ERR_MSG_MAX];
    ct_mkdir(dir, sizeof dir);
    struct loaded L;
    int rc = expand(dir,
                    "name: counts\n" CRYSTAL "sweep:\n"
                    "  grid:\n"
                    "    potential.cutoff: [7.5, 9.0, 10.5]\n"
                    "    crystal.cells: [2, 3]\n"
                    "  zip:\n"
                    "    crystal.a_min: [3.3, 3.4]\n"
                    "    crystal.a_max: [3.9, 3.8]\n"
                    "repeats: 2\n",
                    &L, msg, sizeof msg);
    cr_assert_eq(rc, 0, "%s", msg);
    /* 3 cutoffs x 2 cell counts x 2 zipped pairs x 2 seeds */
    cr_assert_eq(L.p.njobs, 24);
    cr_assert_eq(L.s.ngroups, 4);
    /* the last job: cutoff 10.5, 3 cells, (3.4, 3.8), seed 2 (base seed 1 + 1) */
    json_t *c = json_loads(L.p.jobs[23].case_json, 0, NULL);
    cr_assert_float_eq(json_real_value(json_object_get(json_object_get(c, "potential"), "cutoff")),
                       10.5, 0);
    cr_assert_eq(json_integer_value(json_object_get(json_object_get(c, "crystal"), "cells")), 3);
    cr_assert_float_eq(json_real_value(json_object_get(json_object_get(c, "crystal"), "a_min")),
                       3.4, 0);
    cr_assert_eq(json_integer_value(json_object_get(c, "seed")), 2);
    /* defaults come from the solver: Sutton-Chen epsilon of Chen et al. 2014 */
    cr_assert_float_eq(json_real_value(json_object_get(json_object_get(c, "potential"), "epsilon")),
                       1.2382e-2, 1e-12);
    json_decref(c);
    /* all keys distinct, 16 hex digits */
    for (long j = 0; j < L.p.njobs; j++) {
        cr_assert_eq(strlen(L.p.jobs[j].key), 16);
        for (long k = 0; k < j; k++)
            cr_assert_str_neq(L.p.jobs[j].key, L.p.jobs[k].key);
    }
    unload(&L);
    ct_rmrf(dir);
}

Test(campaign_study, keys_stable_under_key_order)
{
    char dir[64], msg[ERR_MSG_MAX];
    ct_mkdir(dir, sizeof dir);
    struct loaded A, B;
    cr_assert_eq(expand(dir,
                        "name: order\n" CRYSTAL "sweep:\n  grid:\n"
                        "    potential.cutoff: [7.5, 9.0]\n    crystal.cells: [2, 3]\n",
                        &A, msg, sizeof msg),
                 0, "%s", msg);
    /* the same study: keys of the base and the axes written in another order,
     * an integer written where the solver wants a real (normalised) */
    cr_assert_eq(expand(dir,
                        "sweep:\n  grid:\n    crystal.cells: [2, 3]\n"
                        "    potential.cutoff: [7.5, 9]\n"
                        "base:\n  potential: {style: sutton_chen}\n"
                        "  crystal: {a_max: 3.8, element: Cu, a_min: 3.4, lattice: fcc}\n"
                        "  type: crystal\n"
                        "name: order\n",
                        &B, msg, sizeof msg),
                 0, "%s", msg);
    cr_assert_eq(A.p.njobs, 4);
    cr_assert_eq(B.p.njobs, 4);
    for (long j = 0; j < 4; j++) {
        int found = 0;
        for (long k = 0; k < 4; k++)
            found += strcmp(A.p.jobs[j].key, B.p.jobs[k].key) == 0;
        cr_assert_eq(found, 1, "key %s of the first study is missing from the second",
                     A.p.jobs[j].key);
    }
    /* the key is the solver's: cascade-solver resolve --key on the job's case */
    const char *cf = ct_write(1, dir, "case.json", A.p.jobs[3].case_json);
    char out[256];
    const char *argv[] = {th_solver(), "resolve", "--key", cf, NULL};
    cr_assert_eq(ct_exec(dir, NULL, argv, out, sizeof out), 0, "%s", out);
    cr_assert(strncmp(out, A.p.jobs[3].key, 16) == 0, "solver key %s, plan key %s", out,
              A.p.jobs[3].key);
    unload(&A);
    unload(&B);
    ct_rmrf(dir);
}

Test(campaign_study, prep_reference_changes_key)
{
    char dir[64], msg[ERR_MSG_MAX];
    ct_mkdir(dir, sizeof dir);
    struct loaded A, B;
    const char *fmt = "name: prep\n"
                      "base:\n"
                      "  system: {read_xyz: '${prep.eq}/final.xyz'}\n"
                      "  potential: {style: sutton_chen}\n"
                      "prep:\n"
                      "  eq:\n"
                      "    base:\n"
                      "      system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, element: Cu}\n"
                      "      potential: {style: sutton_chen}\n"
                      "      md: {steps: %d}\n"
                      "sweep: {grid: {md.timestep: [0.001, 0.002]}}\n";
    char text[2048];
    snprintf(text, sizeof text, fmt, 100);
    cr_assert_eq(expand(dir, text, &A, msg, sizeof msg), 0, "%s", msg);
    snprintf(text, sizeof text, fmt, 200);
    cr_assert_eq(expand(dir, text, &B, msg, sizeof msg), 0, "%s", msg);
    cr_assert_eq(A.p.njobs, 3);
    cr_assert_eq(A.p.nprep, 1);
    cr_assert_eq(A.p.jobs[1].ndeps, 1);
    cr_assert_eq(A.p.jobs[1].deps[0], 0);
    /* the case holds the preparation job's key, so a changed prep changes every key */
    char ref[64];
    snprintf(ref, sizeof ref, "${prep:%s}/final.xyz", A.p.jobs[0].key);
    cr_assert_not_null(strstr(A.p.jobs[1].case_json, ref), "%s", A.p.jobs[1].case_json);
    cr_assert_str_neq(A.p.jobs[0].key, B.p.jobs[0].key);
    cr_assert_str_neq(A.p.jobs[1].key, B.p.jobs[1].key);
    cr_assert_str_neq(A.p.jobs[2].key, B.p.jobs[2].key);
    unload(&A);
    unload(&B);
    ct_rmrf(dir);
}

/* Expect a study to be rejected with a message holding each of the parts. */
static void expect_error(const char *dir, const char *text, const char *const *parts)
{
    struct loaded L;
    char msg[ERR_MSG_MAX];
    int rc = expand(dir, text, &L, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT, "accepted a bad study (rc %d): %s", rc, msg);
    for (int i = 0; parts[i]; i++)
        cr_assert_not_null(strstr(msg, parts[i]), "message lacks '%s': %s", parts[i], msg);
}

Test(campaign_study, bad_input_messages)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    /* a path that is not a solver key: the solver's own message, at the axis */
    expect_error(dir, "name: b\n" CRYSTAL "sweep:\n  grid:\n    potential.cutof: [7.5, 9.0]\n",
                 (const char *const[]){"study.yaml:8:5:", "sweep.grid.potential.cutof",
                                       "unknown key; did you mean 'cutoff'?", NULL});
    /* a value the solver refuses: at that value */
    expect_error(dir, "name: b\n" CRYSTAL "sweep:\n  grid:\n    potential.cutoff: [7.5, -2]\n",
                 (const char *const[]){"study.yaml:8:29:", "sweep.grid.potential.cutoff[1]",
                                       "must be > 0", NULL});
    /* an empty axis */
    expect_error(dir, "name: b\n" CRYSTAL "sweep:\n  grid:\n    potential.cutoff: []\n",
                 (const char *const[]){"study.yaml:8:5:", "empty axis", NULL});
    /* duplicate values, as written and after the solver's normalisation */
    expect_error(dir, "name: b\n" CRYSTAL "sweep:\n  grid:\n    potential.cutoff: [7.5, 9.0, 7.5]\n",
                 (const char *const[]){"study.yaml:8:34:", "duplicate value 7.5", NULL});
    expect_error(dir, "name: b\n" CRYSTAL "sweep:\n  grid:\n    potential.cutoff: [9, 9.0]\n",
                 (const char *const[]){"study.yaml:8:", "duplicate values", "same case", NULL});
    /* an axis swept twice */
    expect_error(dir,
                 "name: b\n" CRYSTAL "sweep:\n  grid:\n    potential.cutoff: [7.5]\n"
                 "  zip:\n    potential.cutoff: [8.0, 9.0]\n    crystal.cells: [2, 3]\n",
                 (const char *const[]){"study.yaml:10:5:", "swept twice", "line 8", NULL});
    /* zipped axes of unequal length */
    expect_error(dir,
                 "name: b\n" CRYSTAL "sweep:\n  zip:\n    potential.cutoff: [8.0, 9.0]\n"
                 "    crystal.cells: [2, 3, 4]\n",
                 (const char *const[]){"study.yaml:9:5:", "unequal length", NULL});
    /* a missing base case, and a base file that does not exist */
    expect_error(dir, "name: b\nsweep:\n  grid:\n    potential.cutoff: [7.5]\n",
                 (const char *const[]){"study.yaml:1:1:", "missing required key 'base'", NULL});
    expect_error(dir, "name: b\nbase: no_such_case.yaml\n",
                 (const char *const[]){"study.yaml:2:1:", "cannot open base case", NULL});
    /* a misspelt study key, a reference to no preparation job */
    expect_error(dir, "name: b\n" CRYSTAL "retires: 2\n",
                 (const char *const[]){"study.yaml:6:1:", "did you mean 'retries'", NULL});
    expect_error(dir, "name: b\n" CRYSTAL "set: {crystal.element: '${prep.eq}'}\n",
                 (const char *const[]){"study.yaml:6:", "no preparation job named 'eq'", NULL});
    ct_rmrf(dir);
}

Test(campaign_study, bad_input_writes_nothing)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "good.yaml", "name: good\n" CRYSTAL "sweep: {grid: {potential.cutoff: [7.5]}}\n");
    ct_write(1, dir, "bad.yaml",
             "name: good\n" CRYSTAL "sweep: {grid: {potential.cutoff: [7.5, 9.0]}}\n"
             "set: {crystal.cels: 3}\n");
    /* no database at all after a bad study */
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "bad.yaml", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "bad.yaml:7:7: set.crystal.cels"), "%s", out);
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    cr_assert_neq(access(path, F_OK), 0, "a database was created for a bad study");
    /* an existing database is left exactly as it was */
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "good.yaml", "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    long long runs = ct_int(db, "SELECT count(*) FROM runs");
    long long jobs = ct_int(db, "SELECT count(*) FROM jobs");
    char hash[80];
    ct_text(db, "SELECT spec_hash FROM studies WHERE name = 'good'", hash, sizeof hash);
    sqlite3_close(db);
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "bad.yaml", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), runs);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), jobs);
    char hash2[80];
    ct_text(db, "SELECT spec_hash FROM studies WHERE name = 'good'", hash2, sizeof hash2);
    cr_assert_str_eq(hash, hash2);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_study, shipped_studies_expand)
{
    /* every study in studies/ is valid for the solver, with the jobs it says */
    const struct {
        const char *file;
        long njobs;
        int nprep;
    } studies[] = {{"studies/demo.yaml", 7, 1}, {"studies/md_timestep.yaml", 13, 1},
                   {"studies/sc_cutoff.yaml", 6, 0}, {"studies/nightly.yaml", 8, 0}};
    for (size_t i = 0; i < sizeof studies / sizeof studies[0]; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", th_root(), studies[i].file);
        struct study s;
        struct solver sv;
        struct plan p;
        struct err e = {0};
        cr_assert_eq(study_load(&s, path, &e), 0, "%s", e.msg);
        cr_assert_eq(solver_open(&sv, th_solver(), &e), 0, "%s", e.msg);
        cr_assert_eq(plan_build(&p, &s, &sv, &e), 0, "%s: %s", studies[i].file, e.msg);
        cr_assert_eq(p.njobs, studies[i].njobs, "%s", studies[i].file);
        cr_assert_eq(p.nprep, studies[i].nprep, "%s", studies[i].file);
        plan_free(&p);
        study_free(&s);
    }
}
