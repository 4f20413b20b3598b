/*
 * study_analysis: the numbers of a report, computed from a study's results
 * (rdata.h) and its report settings (report_spec.h); no output here.
 *
 *  - points: one per combination of swept values, repeats (and a swept
 *    `seed`) averaged: mean, standard deviation and count per metric;
 *  - groups: the combinations of the swept values other than the
 *    resolution axis (and the axes zipped with it); each group's points
 *    run along the resolution axis in ascending h;
 *  - conv: per metric and group, the Celik et al. (2008) analysis of the
 *    three finest grids with a value (convergence.h), the order of every
 *    three consecutive grids ("local" orders), the GCI also as an absolute
 *    band in the metric's unit, and flags;
 *  - xseries: per metric, the value against each other swept axis with
 *    numeric values (finest grid, and Richardson-extrapolated), one series
 *    per combination of the remaining axes, with the fits the study asks
 *    for; and metric-against-metric series for fits like Us against up.
 */
#ifndef CASCADE_CAMPAIGN_STUDY_ANALYSIS_H
#define CASCADE_CAMPAIGN_STUDY_ANALYSIS_H

#include <jansson.h>

#include "convergence.h"
#include "fit.h"
#include "rdata.h"
#include "report_spec.h"
#include "resolution.h"

#define SA_LABEL_MAX 512

struct sa_point {
    json_t *params;            /* owned: the swept values, repeat axes left out */
    char key[SA_LABEL_MAX];    /* canonical JSON of params: identifies the point */
    char label[SA_LABEL_MAX];  /* "md.timestep=0.001 md.steps=400" */
    long *jobs;                /* indices into rdata.jobs */
    int njobs;
    int group;                 /* its group */
    double h;                  /* grid size (NaN without a resolution axis) */
    double *mean, *sd;         /* [rdata.nmetrics] over repeats; sd NaN with one value */
    int *n;                    /* values averaged */
};

struct sa_group {
    json_t *params;            /* owned: the values of the non-resolution axes */
    char key[SA_LABEL_MAX];
    char label[SA_LABEL_MAX];  /* "potential.style=eam/alloy", or "all jobs" */
    int *pts;                  /* point indices in ascending h */
    int npts;
};

enum sa_conv_status { SA_OK, SA_FEW, SA_ERROR };

struct sa_conv {
    int metric, group;
    enum sa_conv_status status;
    char note[256];            /* why there is no analysis (few grids, error) */
    int *pts;                  /* the group's points with a finite value, ascending h */
    int npts;
    int finest_missing;        /* a finer grid than those used has no value */
    struct conv_result c;      /* of the three finest in pts */
    double abs_unc;            /* Fs |phi1 - phi2| / (r21^p - 1), in the metric's unit */
    int limit_near_zero;       /* |phi_ext| < |phi1 - phi_ext|: relative measures meaningless */
    double *local_p;           /* [npts]: order of grids i, i+1, i+2 (NaN near the coarse end) */
    int *local_kind;           /* enum conv_kind, or -1 */
    double formal;             /* stated formal order, NaN */
    char flags[256];           /* "oscillatory; p far from the formal order 2" */
    int flagged;
};

struct sa_xseries {
    int metric;
    int xaxis;                 /* the axis on x, or -1 when x is a metric */
    int xmetric;               /* the metric on x, or -1 */
    int fit;                   /* index of the fit in report_spec.fits, or -1 */
    char label[SA_LABEL_MAX];  /* the values of the remaining axes ("all" when none) */
    int n;
    double *x, *y, *yext;      /* sorted by x; y at the finest grid, yext extrapolated (NaN) */
    double *ysd;               /* standard deviation over repeats at the finest grid */
    int fit_ok;
    struct fit_result fr;
};

/* One figure: the series [first, first + n) share metric and x. */
struct sa_xplot {
    int metric, xaxis, xmetric, fit;
    int first, n;
    int logx;
};

struct study_analysis {
    const struct rdata *d;
    const struct report_spec *rs;
    struct resolution res;
    int *metrics;              /* analysed metrics (indices into rdata), in report order */
    int nmetrics;
    struct sa_point *pts;
    int npts;
    struct sa_group *groups;
    int ngroups;
    struct sa_conv *conv;      /* nmetrics x ngroups, metric-major; NULL without resolution axis */
    struct sa_xseries *xs;
    int nxs;
    struct sa_xplot *xplots;
    int nxplots;
    long nsweep, ndone;        /* sweep jobs, and those with a successful run */
    const json_t *refine;      /* borrowed: the adaptive refinement state (refine_state.h), or NULL */
};

/* Build the analysis.  ERR_INPUT for report settings that do not fit the
 * study (an unknown resolution axis, a fit naming an unknown metric). */
int sa_build(struct study_analysis *a, const struct rdata *d, const struct report_spec *rs,
             struct err *e);
void sa_free(struct study_analysis *a);

/* The analysis of metric slot k (index into a->metrics) and group g. */
struct sa_conv *sa_conv_at(const struct study_analysis *a, int k, int g);

/* "name=value name=value" for the entries of a params object; values print
 * compactly (strings bare, numbers shortest, lists and mappings as JSON). */
void sa_params_label(const json_t *params, char *out, size_t len);
/* The same for a job's swept values, in the study's axis order. */
void sa_job_label(const struct rdata *d, const json_t *params, char *out, size_t len);

#endif
