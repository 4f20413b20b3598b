/* th_case: one case run end to end (th_case.h). */
#include "helpers/th_case.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>

#include "helpers/th.h"

json_t *th_run_case(int slot, const char *name, const char *text)
{
    char dir[1200];
    const char *path = th_write_temp(slot, name, text);
    snprintf(dir, sizeof dir, "%s/%s-out", th_temp_dir(), name);
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    static char out[8192];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    char p[1400];
    snprintf(p, sizeof p, "%s/result.json", dir);
    json_t *r = json_load_file(p, 0, NULL);
    cr_assert_not_null(r, "%s", p);
    return r;
}

double th_metric_value(json_t *m, const char *name)
{
    json_t *v = json_object_get(json_object_get(m, name), "value");
    cr_assert(json_is_number(v), "metric %s missing", name);
    return json_number_value(v);
}

void th_expect_type_elastic(int slot, const char *crystal, const char *potential,
                            const char *elastic, json_t *m)
{
    char text[2048];
    snprintf(text, sizeof text, "type: elastic\nseed: 5\ncrystal: %s\npotential: %s\nelastic: %s\n",
             crystal, potential, elastic);
    json_t *re = th_run_case(slot, "elastic.yaml", text);
    json_t *me = json_object_get(re, "metrics");
    static const char *const pairs[][2] = {
        {"lattice_constant", "lattice_constant_T"}, {"c11", "c11_mpm"},
        {"c12", "c12_mpm"},                         {"c44", "c44_mpm"},
        {"c11_err", "c11_T_err"},                   {"c12_err", "c12_T_err"},
        {"c44_err", "c44_T_err"},                   {"thermal_expansion", "thermal_expansion"}};
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
        double x = th_metric_value(me, pairs[k][0]), y = th_metric_value(m, pairs[k][1]);
        cr_expect_float_eq(x, y, 1e-9 * fabs(y) + 1e-12, "%s %.12g, case's %s %.12g",
                           pairs[k][0], x, pairs[k][1], y);
    }
    json_decref(re);
}
