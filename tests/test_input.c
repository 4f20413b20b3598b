/*
 * Case files: YAML reading, validation messages (file:line:col, key, near
 * misses), defaults, canonical form and job keys; and the bad-input
 * behaviour of cascade-solver (message and exit code for each).
 */
#include <criterion/criterion.h>
#include <string.h>

#include "helpers/th.h"
#include "input/case.h"
#include "util/canon.h"
#include "util/yamldoc.h"

static int resolve_text(const char *yaml, char *msg, size_t len, json_t **resolved)
{
    const char *path = th_write_temp(0, "case.yaml", yaml);
    struct case_doc cd;
    struct case_resolved cr;
    struct err e = {0};
    int rc = case_load_file(&cd, path, &e);
    if (!rc)
        rc = case_resolve(&cd, 1, 1, NULL, &cr, &e);
    if (!rc)
        case_resolved_free(&cr);
    snprintf(msg, len, "%s", e.msg);
    if (resolved && !rc)
        *resolved = json_incref(cd.doc);
    case_doc_free(&cd);
    return rc;
}

#define BASE                                                                                      \
    "system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n  element: Cu\n"              \
    "potential:\n  style: eam/alloy\n  file: Cu_mishin1.eam.alloy\n"

Test(input, yaml_types_and_locations)
{
    const char *text = "a: 1\nb: 2.5\nc: true\nd: ~\ne: '7'\nf: [1, x]\ng:\n  h: hello\n";
    json_t *doc;
    struct locmap *locs;
    struct err e = {0};
    cr_assert_eq(yamldoc_load_string(text, strlen(text), "t", &doc, &locs, &e), 0, "%s", e.msg);
    cr_assert(json_is_integer(json_object_get(doc, "a")));
    cr_assert(json_is_real(json_object_get(doc, "b")));
    cr_assert(json_is_true(json_object_get(doc, "c")));
    cr_assert(json_is_null(json_object_get(doc, "d")));
    cr_assert(json_is_string(json_object_get(doc, "e")));
    const struct loc *l = locmap_get(locs, "g.h");
    cr_assert_not_null(l);
    cr_assert_eq(l->key_line, 8);
    cr_assert_eq(l->key_col, 3);
    l = locmap_get(locs, "f[1]");
    cr_assert_eq(l->val_line, 6);
    cr_assert_eq(l->val_col, 8);
    json_decref(doc);
    locmap_destroy(&locs);
}

Test(input, syntax_error_names_line_and_column)
{
    char msg[2048];
    int rc = resolve_text("system:\n  lattice: [1, 2\n", msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "case.yaml:") && strstr(msg, "YAML syntax error"), "%s", msg);
}

Test(input, duplicate_key_rejected)
{
    char msg[2048];
    int rc = resolve_text("seed: 1\nseed: 2\n" BASE, msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "case.yaml:2:1") && strstr(msg, "duplicate key 'seed'"), "%s", msg);
}

Test(input, unknown_key_with_suggestion)
{
    char msg[2048];
    int rc = resolve_text(BASE "md:\n  timestpe: 0.001\n", msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "case.yaml:8:3: md.timestpe: unknown key; did you mean 'timestep'?"),
              "%s", msg);
}

Test(input, unknown_value_with_suggestion)
{
    char msg[2048];
    int rc = resolve_text("system:\n  lattice: {style: fcx, a: 3.6}\n  element: Cu\n"
                          "potential: {style: sutton_chen}\n",
                          msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "case.yaml:2:20: system.lattice.style: unknown value 'fcx'; did you "
                          "mean 'fcc'?"),
              "%s", msg);
}

Test(input, wrong_type)
{
    char msg[2048];
    int rc = resolve_text(BASE "md:\n  steps: lots\n", msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "case.yaml:8:10: md.steps: must be an integer, found a string"), "%s",
              msg);
}

Test(input, zero_and_negative_sizes)
{
    char msg[2048];
    int rc = resolve_text("system:\n  lattice: {style: fcc, a: -3.6, cells: [3, 3, 3]}\n"
                          "  element: Cu\npotential: {style: sutton_chen}\n",
                          msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "system.lattice.a: must be > 0 (got -3.6)"), "%s", msg);
    rc = resolve_text("system:\n  lattice: {style: fcc, a: 3.6, cells: [3, 0, 3]}\n"
                      "  element: Cu\npotential: {style: sutton_chen}\n",
                      msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "system.lattice.cells[1]: must be >= 1 (got 0)"), "%s", msg);
    rc = resolve_text(BASE "md:\n  timestep: 0\n", msg, sizeof msg, NULL);
    cr_assert(strstr(msg, "md.timestep: must be > 0 (got 0)"), "%s", msg);
}

Test(input, missing_required_key)
{
    char msg[2048];
    int rc = resolve_text("system:\n  lattice: {style: fcc, cells: [3, 3, 3]}\n  element: Cu\n"
                          "potential: {style: sutton_chen}\n",
                          msg, sizeof msg, NULL);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "case.yaml:2:3: system.lattice: missing required key 'a'"), "%s", msg);
}

Test(input, defaults_filled_and_key_stable_under_reordering)
{
    char msg[2048];
    json_t *r1 = NULL, *r2 = NULL;
    cr_assert_eq(resolve_text(BASE "md: {steps: 10, timestep: 0.001}\nseed: 3\n", msg, sizeof msg,
                              &r1),
                 0, "%s", msg);
    cr_assert_eq(resolve_text("seed: 3\nmd: {timestep: 1e-3, steps: 10}\npotential:\n"
                              "  file: Cu_mishin1.eam.alloy\n  style: eam/alloy\nsystem:\n"
                              "  element: Cu\n  lattice: {cells: [3, 3, 3], a: 3.615, style: fcc}\n",
                              msg, sizeof msg, &r2),
                 0, "%s", msg);
    /* defaults present */
    json_t *md = json_object_get(r1, "md");
    cr_assert(json_is_real(json_object_get(md, "skin")));
    cr_assert_str_eq(json_string_value(json_object_get(r1, "type")), "md");
    char k1[CANON_KEY_LEN + 1], k2[CANON_KEY_LEN + 1];
    canon_key(r1, k1);
    canon_key(r2, k2);
    cr_assert_str_eq(k1, k2);
    /* a changed value changes the key; 2 and 2.0 for a real key do not */
    json_object_set_new(md, "steps", json_integer(11));
    canon_key(r1, k1);
    cr_assert_str_neq(k1, k2);
    json_decref(r1);
    json_decref(r2);
    cr_assert_eq(resolve_text(BASE "md: {skin: 2}\n", msg, sizeof msg, &r1), 0);
    cr_assert_eq(resolve_text(BASE "md: {skin: 2.0}\n", msg, sizeof msg, &r2), 0);
    canon_key(r1, k1);
    canon_key(r2, k2);
    cr_assert_str_eq(k1, k2);
    json_decref(r1);
    json_decref(r2);
}

/* --- the solver program on bad input ---------------------------------- */

static int solver(const char *cmd, const char *yaml, char *out, size_t len)
{
    const char *path = th_write_temp(1, "bad.yaml", yaml);
    char outdir[512];
    snprintf(outdir, sizeof outdir, "%s/out", th_temp_dir());
    const char *argv[] = {th_solver(), cmd, path, "--out", outdir, "--quiet", NULL};
    if (strcmp(cmd, "run") != 0)
        argv[3] = NULL;
    return th_run(argv, out, len);
}

Test(cli, missing_potential_file)
{
    char out[4096];
    int rc = solver("check",
                    "system:\n  lattice: {style: fcc, a: 3.6, cells: [2, 2, 2]}\n  element: Cu\n"
                    "potential:\n  style: eam/alloy\n  file: nowhere.eam.alloy\n",
                    out, sizeof out);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:6:9: potential.file: potential file 'nowhere.eam.alloy' not "
                          "found"),
              "%s", out);
}

Test(cli, corrupt_potential_file)
{
    const char *pot = th_write_temp(2, "broken.eam.alloy",
                                    "c1\nc2\nc3\n1 Cu\n100 0.01 100 0.05 5.0\n29 63.55 3.615 FCC\n"
                                    "0.0 -1.0 -2.0 oops\n");
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "system:\n  lattice: {style: fcc, a: 3.6, cells: [2, 2, 2]}\n  element: Cu\n"
             "potential:\n  style: eam/alloy\n  file: %s\n",
             pot);
    char out[4096];
    int rc = solver("check", yaml, out, sizeof out);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "potential.file: corrupt or unreadable EAM file:") &&
                  strstr(out, "broken.eam.alloy:7: expected a number (value 4 of F(rho) of Cu), "
                              "found 'oops'"),
              "%s", out);
}

Test(cli, unreadable_data_file)
{
    char out[4096];
    int rc = solver("check",
                    "system:\n  read_data: /nonexistent/x.data\npotential: {style: sutton_chen}\n",
                    out, sizeof out);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:2:14: system.read_data: cannot read '/nonexistent/x.data'"),
              "%s", out);
}

Test(cli, malformed_data_file)
{
    const char *data = th_write_temp(3, "m.data",
                                     "title\n\n2 atoms\n1 atom types\n0 10 xlo xhi\n0 10 ylo yhi\n"
                                     "0 10 zlo zhi\n\nMasses\n\n1 63.5 # Cu\n\nAtoms # atomic\n\n"
                                     "1 1 0 0 0\n2 3 1 1 1\n");
    char yaml[1024];
    snprintf(yaml, sizeof yaml, "system:\n  read_data: %s\npotential: {style: sutton_chen}\n", data);
    char out[4096];
    int rc = solver("check", yaml, out, sizeof out);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "m.data:16: atom type 3 out of range 1..1"), "%s", out);
}

Test(cli, unstable_time_step_refused)
{
    char out[4096];
    int rc = solver("run", BASE "md: {timestep: 0.1, steps: 10}\n", out, sizeof out);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:") && strstr(out, "md.timestep: time step 0.1 ps is unstable"),
              "%s", out);
}

Test(cli, unknown_command_and_help)
{
    char out[8192];
    const char *argv1[] = {th_solver(), "frobnicate", NULL};
    cr_assert_eq(th_run(argv1, out, sizeof out), 2);
    cr_assert(strstr(out, "unknown command 'frobnicate'"));
    const char *cmds[] = {"run", "check", "resolve", "info"};
    for (int k = 0; k < 4; k++) {
        const char *argv2[] = {th_solver(), cmds[k], "--help", NULL};
        cr_assert_eq(th_run(argv2, out, sizeof out), 0);
        cr_assert(strstr(out, "usage: cascade-solver"), "%s", out);
    }
    const char *argv3[] = {th_solver(), "run", "x.yaml", "--threads", "zero", NULL};
    cr_assert_eq(th_run(argv3, out, sizeof out), 2);
    cr_assert(strstr(out, "--threads needs an integer"), "%s", out);
}

Test(cli, batch_resolve_answers_every_line)
{
    const char *in = th_write_temp(4, "batch.jsonl",
                                   "{\"system\": {\"lattice\": {\"style\": \"fcc\", \"a\": 3.6}, "
                                   "\"element\": \"Cu\"}, \"potential\": {\"style\": \"sutton_chen\"}}\n"
                                   "{\"system\": {}, \"bogus\": 1}\nnot json\n");
    char cmd[1024], out[16384];
    snprintf(cmd, sizeof cmd, "%s resolve --batch < %s", th_solver(), in);
    const char *argv[] = {"/bin/sh", "-c", cmd, NULL};
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    char *l1 = out, *l2 = strchr(l1, '\n') + 1, *l3 = strchr(l2, '\n') + 1;
    cr_assert(strncmp(l1, "{\"case\":", 8) == 0 && strstr(l1, "\"key\":") && strstr(l1, "\"ok\":true"),
              "%s", l1);
    cr_assert(strstr(l2, "\"ok\":false") && strstr(l2, "<stdin line 2>"), "%s", l2);
    cr_assert(strstr(l3, "\"ok\":false") && strstr(l3, "invalid JSON"), "%s", l3);
}

/* Non-finite and malformed numbers in configuration files: each is refused
 * at read time with file:line and the field (a NaN coordinate crashed the
 * spatial sort of `check` and `run` before). */
Test(cli, nonfinite_and_malformed_coordinates_refused)
{
    static const struct {
        const char *atom_line;   /* the second atom of a LAMMPS data file */
        const char *expect;
    } data_cases[] = {
        {"2 1 nan 1 1", "m.data:16: Atoms line: field 3 (x) must be a finite decimal number, found 'nan'"},
        {"2 1 1 inf 1", "field 4 (y) must be a finite decimal number, found 'inf'"},
        {"2 1 1 1 1e999", "field 5 (z) must be a finite decimal number, found '1e999'"},
        {"2 1 1 1 -INF", "field 5 (z) must be a finite decimal number, found '-INF'"},
        {"2 1 0x10 1 1", "field 3 (x) must be a finite decimal number, found '0x10'"},
        {"2 1 1xyz.785 1 1", "field 3 (x) must be a finite decimal number, found '1xyz.785'"},
        {"2.5 1 1 1 1", "m.data:16: Atoms line: id 2.5 is not a positive integer"},
        {"2 1e300 1 1 1", "m.data:16: atom type 1e+300 out of range 1..1"},
        {"2 1 1 1 1 0 1e99 0", "m.data:16: Atoms line: image flag 1e+99 is not an integer"},
    };
    for (size_t k = 0; k < sizeof data_cases / sizeof data_cases[0]; k++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "title\n\n2 atoms\n1 atom types\n0 10 xlo xhi\n0 10 ylo yhi\n"
                 "0 10 zlo zhi\n\nMasses\n\n1 63.5 # Cu\n\nAtoms # atomic\n\n"
                 "1 1 0 0 0\n%s\n", data_cases[k].atom_line);
        const char *data = th_write_temp(3, "m.data", text);
        char yaml[1024], out[4096];
        snprintf(yaml, sizeof yaml, "system:\n  read_data: %s\npotential: {style: sutton_chen}\n",
                 data);
        int rc = solver("check", yaml, out, sizeof out);
        cr_assert_eq(rc, 2, "'%s': %s", data_cases[k].atom_line, out);
        cr_assert(strstr(out, data_cases[k].expect), "'%s': %s", data_cases[k].atom_line, out);
    }
    static const struct {
        const char *atom_line;
        const char *expect;
    } xyz_cases[] = {
        {"Cu nan 1 1", "m.xyz:4: pos (column 2): 'nan' is not a finite decimal number"},
        {"Cu 1 1 inf", "m.xyz:4: pos (column 4): 'inf' is not a finite decimal number"},
        {"Cu 1 1e999 1", "m.xyz:4: pos (column 3): '1e999' is not a finite decimal number"},
        {"Cu 0x1p3 1 1", "m.xyz:4: pos (column 2): '0x1p3' is not a finite decimal number"},
    };
    for (size_t k = 0; k < sizeof xyz_cases / sizeof xyz_cases[0]; k++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "2\nLattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:3 "
                 "pbc=\"T T T\"\nCu 0 0 0\n%s\n", xyz_cases[k].atom_line);
        const char *xyz = th_write_temp(3, "m.xyz", text);
        char yaml[1024], out[4096];
        snprintf(yaml, sizeof yaml, "system:\n  read_xyz: %s\npotential: {style: sutton_chen}\n",
                 xyz);
        int rc = solver("check", yaml, out, sizeof out);
        cr_assert_eq(rc, 2, "'%s': %s", xyz_cases[k].atom_line, out);
        cr_assert(strstr(out, xyz_cases[k].expect), "'%s': %s", xyz_cases[k].atom_line, out);
    }
}
