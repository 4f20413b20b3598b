/*
 * refine_spec: the `refine:` section of a study -- adaptive refinement
 * along its resolution axis (refine_run.h; docs/reports.md):
 *
 *   refine:
 *     axis: grid.cell              # the swept resolution axis (default: report.resolution)
 *     metrics: [wave_speed]        # the metrics that must converge (or metric: NAME)
 *     ratio: 2                     # refinement ratio of h from level to level (> 1)
 *     until:                       # every criterion given must hold for every metric
 *       gci: 0.01                  #   fine-grid GCI (a fraction: 0.01 = 1 %)
 *       band: 5.0                  #   GCI in the metric's unit (for a limit near 0)
 *       asymptotic: 0.1            #   |GCI_32 / (r21^p GCI_21) - 1| (true: 0.1)
 *     max_levels: 6                # levels of a series at most (the start levels count)
 *     budget: {core_hours: 20}     # or {core_seconds: N}: cores x wall of the study's jobs
 *     follow: {md.steps: inverse}  # keys zipped with the axis: inverse (x ratio per
 *                                  # level), value (/ ratio) or same
 *
 * The start levels are the values the sweep gives the axis (three or
 * more).  Checks that need the study (swept keys, metrics, the factor of
 * the axis) are study.c's.
 */
#ifndef CASCADE_CAMPAIGN_REFINE_SPEC_H
#define CASCADE_CAMPAIGN_REFINE_SPEC_H

#include "docpath.h"
#include "util/cfg.h"

enum refine_follow { FOLLOW_INVERSE, FOLLOW_VALUE, FOLLOW_SAME };
extern const char *const refine_follow_names[];   /* "inverse", "value", "same" */

#define REFINE_MAX_METRICS 16
#define REFINE_MAX_FOLLOW 8

struct refine_spec {
    int on;                          /* the section is present */
    char axis[DOCPATH_MAX];          /* "" : the report's resolution axis */
    char metrics[REFINE_MAX_METRICS][128];
    int nmetrics;
    double ratio;
    double gci, band, asymptotic;    /* NaN: not required */
    long max_levels;
    double budget_core_s;            /* INFINITY: no budget */
    struct {
        char path[DOCPATH_MAX];
        enum refine_follow how;
    } follow[REFINE_MAX_FOLLOW];
    int nfollow;
};

void refine_spec_init(struct refine_spec *r);
/* Read `refine:` of a study document (marks it known on root). */
int refine_spec_read(struct cfg_obj *root, struct refine_spec *r);

#endif
