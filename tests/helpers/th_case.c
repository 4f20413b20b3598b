/* th_case: one case run end to end (th_case.h). */
#include "helpers/th_case.h"

#include <criterion/criterion.h>
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
