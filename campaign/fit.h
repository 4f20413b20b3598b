/*
 * fit: least-squares fits for the tables of a report -- a straight line
 * y = a + b x (the Hugoniot Us = c0 + s up) and a power law y = A x^k
 * (a straight line in log-log), with standard errors and R^2.
 */
#ifndef CASCADE_CAMPAIGN_FIT_H
#define CASCADE_CAMPAIGN_FIT_H

#include "report_spec.h"

struct fit_result {
    enum fit_model model;
    int n;              /* points used (finite; positive for a power law) */
    double p0, p1;      /* linear: a, b; power: A, k */
    double s0, s1;      /* standard errors (NaN with two points) */
    double r2;          /* coefficient of determination (of the fitted line) */
    double rms;         /* root-mean-square residual in y */
};

/* Fit the finite points (x, y).  Returns 0, or -1 with fewer than two
 * usable points or all x equal. */
int fit_points(enum fit_model model, const double *x, const double *y, int n,
               struct fit_result *f);

/* The fitted y at x. */
double fit_eval(const struct fit_result *f, double x);

/* A gnuplot expression in x for the fitted curve ("1.23 + 4.56*x"). */
void fit_expr(const struct fit_result *f, char *out, size_t len);

#endif
