/*
 * report_spec: what a study file says about its report and its regression
 * check -- the optional sections `report:` and `regress:` (docs/reports.md).
 *
 *   report:
 *     resolution:                   # the resolution axis (a string is short for {axis: ...});
 *       axis: md.timestep           # `none` says there is none; absent: inferred (resolution.h)
 *       h: value                    # value | inverse | cells: how an axis value maps to h
 *       dim: 3                      # cells: dimension (default: the list length, or 1)
 *       volume: 1.0                 # cells: length / area / volume of the domain
 *       label: time step (ps)       # axis label of the plots
 *     order: 2                      # formal order, or {default: 2, temperature_mean: 1}
 *     safety: 1.25                  # GCI safety factor Fs (Celik et al. 2008: 1.25)
 *     metrics: [pe_per_atom, ...]   # metrics to analyse (default: every recorded one)
 *     axes:                         # plot options of the other swept axes
 *       cluster.atoms: {label: cluster size (atoms), log: true}
 *     fits:                         # least-squares fits against an axis or a metric
 *       - {metric: us, against: up_piston, model: linear, names: [c0, s]}
 *       - {metric: v, against: e, model: power, range: [1, 10]}   # only 1 <= e <= 10
 *   regress:
 *     baseline: baselines/nightly.json   # relative to the study file
 *     tolerances:                   # |now - baseline| <= abs + rel |baseline|
 *       default: {abs: 0, rel: 1.0e-9}
 *       pe_per_atom: {abs: 1.0e-7, rel: 0, order: 0.02}
 *     order: 0.05                   # default tolerance on observed orders (absolute)
 *
 * The reader checks types and bounds (file:line:col messages through cfg);
 * the names of axes and metrics are checked by the caller, which knows the
 * study (study.c) or the database (cmd_report.c).
 */
#ifndef CASCADE_CAMPAIGN_REPORT_SPEC_H
#define CASCADE_CAMPAIGN_REPORT_SPEC_H

#include <stddef.h>

#include "docpath.h"
#include "util/cfg.h"
#include "util/err.h"

#define RSPEC_NAME_MAX 128
#define RSPEC_LABEL_MAX 128

enum res_mode { RES_INFER, RES_NONE, RES_AXIS };
enum hmap { HMAP_INFER = -1, HMAP_VALUE = 0, HMAP_INVERSE, HMAP_CELLS };
extern const char *const hmap_names[];   /* "value", "inverse", "cells" */

enum fit_model { FIT_LINEAR, FIT_POWER };
extern const char *const fit_model_names[];   /* "linear", "power" */

struct rspec_order {
    char metric[RSPEC_NAME_MAX];
    double order;
};

struct rspec_axis {
    char path[DOCPATH_MAX];
    char label[RSPEC_LABEL_MAX];
    int log;                        /* 1, 0, or -1: decide from the values */
};

struct rspec_fit {
    char metric[RSPEC_NAME_MAX];
    char against[DOCPATH_MAX];      /* a swept axis or a metric */
    char along[DOCPATH_MAX];        /* metric against metric: the axis the series runs along ("") */
    enum fit_model model;
    char names[2][32];              /* parameter names: intercept/slope (linear), prefactor/exponent (power) */
    int extrapolated;               /* fit the Richardson-extrapolated values, not the finest grid's */
    int has_range;                  /* fit only the points with range[0] <= x <= range[1] */
    double range[2];
    char where[64];                 /* "report.fits[2]" */
};

struct rspec_tol {
    char metric[RSPEC_NAME_MAX];    /* "" for the default */
    double abs, rel;
    double order;                   /* tolerance on the observed order; NaN: the default */
};

struct report_spec {
    /* report */
    enum res_mode res_mode;
    char res_axis[DOCPATH_MAX];
    enum hmap hmap;
    long dim;                       /* 0: from the values */
    double volume;
    char res_label[RSPEC_LABEL_MAX];
    double order_default;           /* NaN: not stated */
    struct rspec_order *orders;
    int norders;
    double safety;
    char **metrics;                 /* NULL: all */
    int nmetrics;
    struct rspec_axis *axes;
    int naxes;
    struct rspec_fit *fits;
    int nfits;
    /* regress */
    char baseline[4096];            /* as written ("" : baselines/<study>.json) */
    struct rspec_tol tol_default;
    struct rspec_tol *tols;
    int ntols;
    double order_tol;               /* default tolerance on observed orders */
};

/* Defaults (no sections written). */
void report_spec_init(struct report_spec *rs);
/* Read the `report` and `regress` sections of a study document (marks them
 * known on root; leaves the other keys alone). */
int report_spec_read(struct cfg_obj *root, struct report_spec *rs);
/* Parse only those sections from a study file's text (the copy the database
 * keeps); `name` is used in messages. */
int report_spec_from_text(const char *text, size_t len, const char *name, struct report_spec *rs,
                          struct err *e);
void report_spec_free(struct report_spec *rs);

/* The formal order for a metric (NaN when not stated). */
double report_spec_order(const struct report_spec *rs, const char *metric);
/* Plot options of an axis, or NULL. */
const struct rspec_axis *report_spec_axis(const struct report_spec *rs, const char *path);
/* Tolerances for a metric (the default when it has none of its own). */
void report_spec_tol(const struct report_spec *rs, const char *metric, double *abs, double *rel,
                     double *order);
/* Whether the study wants this metric analysed. */
int report_spec_wants(const struct report_spec *rs, const char *metric);

#endif
