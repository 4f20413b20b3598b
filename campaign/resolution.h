/*
 * resolution: which swept axis of a study is its resolution axis, and how
 * one of its values maps to the grid size h of the convergence analysis
 * (convergence.h needs only ratios of h, so the unit of h does not matter).
 *
 *   h: value     h is the value itself (a cell edge, a time step)
 *   h: inverse   h = 1 / value (a cutoff radius, particles per length)
 *   h: cells     the value is a cell count N, or a list [nx, ny, nz] whose
 *                product is N: h = (volume / N)^(1/dim)   (Celik et al.
 *                2008, Eq. 1), dim = the list length unless given
 *
 * A one-element list [x] counts as the number x (for keys that take lists).
 *
 * When the study does not say (report.resolution absent), an axis is taken
 * as the resolution axis only when its name says so: its last component is
 * one of timestep, dt, dx, h, cell, cell_size, cell_edge, cell_length,
 * spacing, grid_spacing, mesh_size, element_size, resolution, and its values
 * are positive numbers.  When several axes qualify, a spatial one (not
 * timestep/dt) wins if it is the only spatial one; otherwise none is chosen
 * and the report says so.  The mapping, when not given, is `cells` for
 * lists of integers, `inverse` for a name containing "cutoff", `value`
 * otherwise.
 */
#ifndef CASCADE_CAMPAIGN_RESOLUTION_H
#define CASCADE_CAMPAIGN_RESOLUTION_H

#include <jansson.h>

#include "report_spec.h"

struct res_axis_info {
    const char *name;
    int grp;                 /* product factor (zipped axes share it) */
    int repeat;              /* a repeat (seed) axis: averaged over, never a resolution */
    const json_t *values;    /* the list of values */
};

struct resolution {
    int axis;                /* index into the axes, or -1: no resolution axis */
    int grp;                 /* its factor (-1 when none) */
    enum hmap hmap;
    long dim;                /* cells: 0 = from each value (list length, or 1) */
    double volume;
    int inferred;            /* the axis was inferred from its name */
    int map_inferred;        /* the mapping was inferred */
    char label[RSPEC_LABEL_MAX];   /* plot label of h */
    char axis_words[RSPEC_LABEL_MAX + 64];   /* what h is, for titles: "the time step
                                               md.timestep", "1 / sc.cutoff" */
    char why[512];           /* how it was chosen, for the report */
};

/* Choose the resolution axis.  Returns ERR_INPUT when the study names an
 * axis that is not swept or whose values cannot map to h. */
int resolution_choose(const struct report_spec *rs, const struct res_axis_info *axes, int n,
                      struct resolution *r, struct err *e);

/* h of one value of the resolution axis (NaN when it does not map). */
double resolution_h(const struct resolution *r, const json_t *value);

/* A number, or the number in a one-element list; NaN otherwise. */
double res_number(const json_t *v);

#endif
