/*
 * MPM case files: the bad inputs the issue lists -- overlapping bodies,
 * points outside the grid, non-positive density or moduli, an unstable time
 * step -- and a few more (unknown material, GIMP on a hierarchical grid, a
 * CFL factor above 1) are each refused with the file, line, column, key and
 * the reason; `cascade-solver check` exits with status 2.  A good case
 * resolves with its defaults filled in.
 */
#include <criterion/criterion.h>
#include <string.h>

#include "helpers/th.h"
#include "input/case.h"

static int check_text(const char *yaml, int shallow, char *msg, size_t len)
{
    const char *path = th_write_temp(1, "mpm.yaml", yaml);
    struct case_doc cd;
    struct case_resolved cr;
    struct err e = {0};
    int rc = case_load_file(&cd, path, &e);
    if (!rc)
        rc = case_resolve(&cd, shallow, 1, NULL, &cr, &e);
    if (!rc)
        case_resolved_free(&cr);
    snprintf(msg, len, "%s", e.msg);
    case_doc_free(&cd);
    return rc;
}

#define HEAD                                                                                      \
    "type: mpm\n"                                                                                 \
    "mpm:\n"                                                                                      \
    "  units: si\n"                                                                               \
    "  grid: {cell: 0.1, cells: [10, 4, 4]}\n"
#define MATERIAL                                                                                  \
    "  materials:\n"                                                                              \
    "    - {name: al, law: linear_elastic, density: 2700, E: 70.0e9, nu: 0.3}\n"
#define BODY_A                                                                                    \
    "  bodies:\n"                                                                                 \
    "    - {name: A, material: al, region: {shape: box, lo: [0.1, 0.1, 0.1], hi: [0.4, 0.3, "  \
    "0.3]}}\n"

Test(mpm_input, good_case_resolves_with_defaults)
{
    char msg[2048];
    cr_assert_eq(check_text(HEAD MATERIAL BODY_A, 0, msg, sizeof msg), 0, "%s", msg);
    cr_assert_eq(check_text(HEAD MATERIAL BODY_A, 1, msg, sizeof msg), 0, "%s", msg);
}

Test(mpm_input, overlapping_bodies_refused)
{
    char msg[2048];
    int rc = check_text(HEAD MATERIAL BODY_A
                        "    - {name: B, material: al, region: {shape: sphere, center: [0.45, 0.2, "
                        "0.2], radius: 0.1}}\n",
                        0, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.yaml:9:") && strstr(msg, "mpm.bodies[1].region") &&
                  strstr(msg, "body 'B' overlaps body 'A'"),
              "%s", msg);
}

Test(mpm_input, points_outside_grid_refused)
{
    char msg[2048];
    int rc = check_text(HEAD MATERIAL
                        "  bodies:\n"
                        "    - {name: A, material: al, region: {shape: box, lo: [0.5, 0.1, 0.1], "
                        "hi: [1.2, 0.3, 0.3]}}\n",
                        0, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.yaml:8:") && strstr(msg, "mpm.bodies[0].region") &&
                  strstr(msg, "outside the grid") && strstr(msg, "x = [0.5, 1.2] m") &&
                  strstr(msg, "[0, 1] m"),
              "%s", msg);
}

/* A typo in `cells` used to allocate gigabytes before "out of memory"; it
 * is refused when the case is read (also by `resolve`, which is shallow),
 * and the bound is the case's to raise. */
Test(mpm_input, grid_and_points_bounded_before_allocation)
{
    char msg[2048];
    const char *huge = "type: mpm\nmpm:\n  units: si\n"
                       "  grid: {cell: 0.1, cells: [100000, 100000, 100000]}\n" MATERIAL BODY_A;
    for (int shallow = 0; shallow < 2; shallow++) {
        int rc = check_text(huge, shallow, msg, sizeof msg);
        cr_assert_eq(rc, ERR_INPUT);
        cr_assert(strstr(msg, "mpm.yaml:4:") && strstr(msg, "mpm.grid.cells") &&
                      strstr(msg, "1e+15 grid nodes, more than mpm.grid.max_nodes = 50000000 "
                                  "(the default; set it to allow more)"),
                  "%s", msg);
    }
    /* 11 x 5 x 5 = 275 nodes: a bound of 274 refuses the grid, 275 takes it */
    int rc = check_text("type: mpm\nmpm:\n  units: si\n"
                        "  grid: {cell: 0.1, cells: [10, 4, 4], max_nodes: 274}\n" MATERIAL BODY_A,
                        1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "275 grid nodes, more than mpm.grid.max_nodes = 274") &&
                  !strstr(msg, "the default"),
              "%s", msg);
    rc = check_text("type: mpm\nmpm:\n  units: si\n"
                    "  grid: {cell: 0.1, cells: [10, 4, 4], max_nodes: 275}\n" MATERIAL BODY_A,
                    1, msg, sizeof msg);
    cr_assert_eq(rc, 0, "%s", msg);
    /* body A: 3 x 2 x 2 cells of 2^3 points = 96 points; its bounding box
     * spans 4 x 3 x 3 cells' worth of points (288), refused under 288 */
    rc = check_text(HEAD "  max_points: 200\n" MATERIAL BODY_A, 0, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.bodies[0].region") &&
                  strstr(msg, "body 'A' brings the material points to up to 288, more than "
                              "mpm.max_points = 200"),
              "%s", msg);
    rc = check_text(HEAD "  max_points: 288\n" MATERIAL BODY_A, 0, msg, sizeof msg);
    cr_assert_eq(rc, 0, "%s", msg);
}

Test(mpm_input, non_positive_density_and_moduli_refused)
{
    char msg[2048];
    int rc = check_text(HEAD "  materials:\n"
                             "    - {name: al, law: linear_elastic, density: 0, E: 70.0e9, nu: 0.3}\n"
                             BODY_A,
                        1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.yaml:6:") && strstr(msg, "mpm.materials[0].density") &&
                  strstr(msg, "must be positive"),
              "%s", msg);
    rc = check_text(HEAD "  materials:\n"
                         "    - {name: al, law: linear_elastic, density: 2700, E: -70.0e9, nu: 0.3}\n"
                         BODY_A,
                    1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.materials[0].E") && strstr(msg, "Young's modulus") &&
                  strstr(msg, "must be positive"),
              "%s", msg);
    rc = check_text(HEAD "  materials:\n"
                         "    - {name: cu, law: cubic_elastic, density: 8960, C11: 170e9, C12: "
                         "120e9, C44: 0}\n" BODY_A,
                    1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.materials[0].C44") && strstr(msg, "must be positive"), "%s", msg);
    rc = check_text(HEAD "  materials:\n"
                         "    - {name: s, law: j2, density: 7800, E: 200e9, nu: 0.3, yield: -1}\n"
                         BODY_A,
                    1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.materials[0].yield") && strstr(msg, "must be positive"), "%s", msg);
}

Test(mpm_input, unstable_time_step_refused)
{
    char msg[2048];
    /* h / c = 0.1 m / 5908 m/s = 1.69e-5 s */
    int rc = check_text(HEAD MATERIAL BODY_A "  timestep: 2.0e-5\n", 0, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.yaml:") && strstr(msg, "mpm.timestep") &&
                  strstr(msg, "is unstable") && strstr(msg, "1.69"),
              "%s", msg);
    cr_assert_eq(check_text(HEAD MATERIAL BODY_A "  timestep: 1.0e-5\n", 0, msg, sizeof msg), 0,
                 "%s", msg);
}

Test(mpm_input, other_mistakes_named)
{
    char msg[2048];
    int rc = check_text(HEAD MATERIAL
                        "  bodies:\n"
                        "    - {name: A, material: steel, region: {shape: box, lo: [0.1, 0.1, "
                        "0.1], hi: [0.4, 0.3, 0.3]}}\n",
                        1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.bodies[0].material") && strstr(msg, "no material named 'steel'"),
              "%s", msg);
    rc = check_text("type: mpm\nmpm:\n  grid: {cell: 1, cells: [8, 4, 4], shape: gimp, levels: "
                    "[{coarsen: xyz, region: {shape: slab, axis: x, lo: 4, hi: 8}}]}\n" MATERIAL
                    BODY_A,
                    1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.grid.shape") && strstr(msg, "uniform grid"), "%s", msg);
    rc = check_text(HEAD MATERIAL BODY_A "  cfl: 1.5\n", 1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "mpm.cfl"), "%s", msg);
    rc = check_text(HEAD MATERIAL BODY_A "  algoritm: usl\n", 1, msg, sizeof msg);
    cr_assert_eq(rc, ERR_INPUT);
    cr_assert(strstr(msg, "did you mean 'algorithm'"), "%s", msg);
}

Test(mpm_input, check_command_exit_status)
{
    const char *path = th_write_temp(2, "bad.yaml",
                                     HEAD MATERIAL BODY_A
                                     "    - {name: B, material: al, region: {shape: box, lo: "
                                     "[0.3, 0.1, 0.1], hi: [0.5, 0.3, 0.3]}}\n");
    const char *argv[] = {th_solver(), "check", path, NULL};
    char out[4096];
    cr_assert_eq(th_run(argv, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "bad.yaml:9:") && strstr(out, "overlaps"), "%s", out);
}
