/* resolution: the resolution axis of a study and its grid size h (see resolution.h). */
#include "resolution.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "convergence.h"

double res_number(const json_t *v)
{
    if (json_is_array(v) && json_array_size(v) == 1)
        v = json_array_get(v, 0);
    return json_is_number(v) ? json_number_value(v) : NAN;
}

/* A cell count: an integer >= 1, or a list of them (their product). */
static double cell_count(const json_t *v, long *len)
{
    *len = 1;
    if (json_is_integer(v))
        return json_integer_value(v) >= 1 ? (double)json_integer_value(v) : NAN;
    if (!json_is_array(v) || json_array_size(v) == 0)
        return NAN;
    double n = 1;
    size_t i;
    json_t *x;
    json_array_foreach(v, i, x)
    {
        if (!json_is_integer(x) || json_integer_value(x) < 1)
            return NAN;
        n *= (double)json_integer_value(x);
    }
    *len = (long)json_array_size(v);
    return n;
}

double resolution_h(const struct resolution *r, const json_t *value)
{
    if (r->axis < 0)
        return NAN;
    if (r->hmap == HMAP_CELLS) {
        long len;
        double n = cell_count(value, &len);
        long dim = r->dim ? r->dim : len;
        return isfinite(n) ? conv_h_from_cells(n, (int)dim, r->volume) : NAN;
    }
    double x = res_number(value);
    if (!(x > 0) || !isfinite(x))
        return NAN;
    return r->hmap == HMAP_INVERSE ? 1.0 / x : x;
}

static const char *last_component(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot ? dot + 1 : path;
}

static int is_time_name(const char *last)
{
    return strcmp(last, "timestep") == 0 || strcmp(last, "dt") == 0;
}

static int is_resolution_name(const char *path)
{
    static const char *const names[] = {"timestep",     "dt",        "dx",          "h",
                                        "cell",         "cell_size", "cell_edge",   "cell_length",
                                        "spacing",      "grid_spacing", "mesh_size", "element_size",
                                        "resolution",   NULL};
    const char *last = last_component(path);
    for (int i = 0; names[i]; i++)
        if (strcmp(last, names[i]) == 0)
            return 1;
    return 0;
}

static enum hmap infer_map(const char *name, const json_t *values)
{
    int all_int_lists = json_array_size(values) > 0;
    size_t i;
    json_t *v;
    json_array_foreach(values, i, v)
    {
        long len;
        if (!json_is_array(v) || json_array_size(v) < 2 || !isfinite(cell_count(v, &len)))
            all_int_lists = 0;
    }
    if (all_int_lists)
        return HMAP_CELLS;
    if (strstr(name, "cutoff"))
        return HMAP_INVERSE;
    return HMAP_VALUE;
}

/* Whether every value maps to a positive, finite h. */
static int maps_all(struct resolution *r, const json_t *values)
{
    size_t i;
    json_t *v;
    json_array_foreach(values, i, v)
    {
        double h = resolution_h(r, v);
        if (!(h > 0) || !isfinite(h))
            return 0;
    }
    return 1;
}

static void describe(struct resolution *r, const char *name, const char *how)
{
    char map[160];
    switch (r->hmap) {
    case HMAP_INVERSE:
        snprintf(map, sizeof map, "h = 1 / %s", name);
        break;
    case HMAP_CELLS:
        if (r->dim)
            snprintf(map, sizeof map, "h = (%g / N)^(1/%ld), N the cell count %s", r->volume,
                     r->dim, name);
        else
            snprintf(map, sizeof map, "h = (%g / N)^(1/dim), N the cell count %s (dim: the "
                                      "number of entries)",
                     r->volume, name);
        break;
    default:
        snprintf(map, sizeof map, "h = %s", name);
    }
    snprintf(r->why, sizeof r->why, "resolution axis %s (%s); %s%s", name, how, map,
             r->map_inferred ? " (mapping inferred; set report.resolution.h to change it)" : "");
}

int resolution_choose(const struct report_spec *rs, const struct res_axis_info *axes, int n,
                      struct resolution *r, struct err *e)
{
    memset(r, 0, sizeof *r);
    r->axis = -1;
    r->grp = -1;
    r->volume = rs->volume;
    r->dim = rs->dim;
    if (rs->res_mode == RES_NONE) {
        snprintf(r->why, sizeof r->why, "no resolution axis (report.resolution: none)");
        return 0;
    }
    int pick = -1;
    if (rs->res_mode == RES_AXIS) {
        for (int i = 0; i < n; i++)
            if (strcmp(axes[i].name, rs->res_axis) == 0)
                pick = i;
        if (pick < 0 || axes[pick].repeat)
            return err_set(e, ERR_INPUT, "report.resolution: '%s' is not a swept axis of the study",
                           rs->res_axis);
    } else {
        int cand[64], nc = 0, nspatial = 0, spatial = -1;
        for (int i = 0; i < n && nc < 64; i++) {
            if (axes[i].repeat || !is_resolution_name(axes[i].name))
                continue;
            struct resolution t = *r;
            t.axis = i;
            t.hmap = infer_map(axes[i].name, axes[i].values);
            if (json_array_size(axes[i].values) < 2 || !maps_all(&t, axes[i].values))
                continue;
            cand[nc++] = i;
            if (!is_time_name(last_component(axes[i].name))) {
                nspatial++;
                spatial = i;
            }
        }
        if (nc == 1)
            pick = cand[0];
        else if (nc > 1 && nspatial == 1)
            pick = spatial;
        if (pick < 0) {
            if (nc > 1)
                snprintf(r->why, sizeof r->why, "no resolution axis: %d axes could be one (%s, %s, "
                                                "...); say which with report.resolution",
                         nc, axes[cand[0]].name, axes[cand[1]].name);
            else
                snprintf(r->why, sizeof r->why, "no resolution axis (none of the swept keys is "
                                                "named like one; set report.resolution to choose)");
            return 0;
        }
        r->inferred = 1;
    }
    r->axis = pick;
    r->grp = axes[pick].grp;
    r->hmap = rs->hmap;
    if (r->hmap == HMAP_INFER) {
        r->hmap = infer_map(axes[pick].name, axes[pick].values);
        r->map_inferred = 1;
    }
    if (!maps_all(r, axes[pick].values)) {
        const char *name = axes[pick].name;
        r->axis = r->grp = -1;
        return err_set(e, ERR_INPUT, "report.resolution: the values of %s do not map to a grid "
                                     "size with h: %s (%s)",
                       name, hmap_names[rs->hmap == HMAP_INFER ? HMAP_VALUE : rs->hmap],
                       rs->hmap == HMAP_CELLS ? "cell counts must be positive integers or lists "
                                                "of them"
                                              : "values must be positive numbers");
    }
    if (rs->res_label[0])
        snprintf(r->label, sizeof r->label, "%s", rs->res_label);
    else if (r->hmap == HMAP_VALUE)
        snprintf(r->label, sizeof r->label, "h = %s", axes[pick].name);
    else if (r->hmap == HMAP_INVERSE)
        snprintf(r->label, sizeof r->label, "h = 1 / %s", axes[pick].name);
    else
        snprintf(r->label, sizeof r->label, "h = (V/N)^{1/dim}, N from %s", axes[pick].name);
    /* figure titles name the axis itself: a time step is no grid size */
    const char *nm = axes[pick].name;
    if (r->hmap == HMAP_INVERSE)
        snprintf(r->axis_words, sizeof r->axis_words, "1 / %s", nm);
    else if (r->hmap == HMAP_CELLS)
        snprintf(r->axis_words, sizeof r->axis_words, "the cell size from %s", nm);
    else if (is_time_name(last_component(nm)))
        snprintf(r->axis_words, sizeof r->axis_words, "the time step %s", nm);
    else
        snprintf(r->axis_words, sizeof r->axis_words, "the grid size %s", nm);
    describe(r, axes[pick].name,
             r->inferred ? "inferred from its name; set report.resolution to change it"
                         : "from report.resolution");
    return 0;
}
