/*
 * eam_table: tabulated functions of an EAM potential as per-interval cubics,
 * built and evaluated exactly as LAMMPS's pair_style eam does, so energies
 * and forces agree with LAMMPS to round-off for the same file.
 *
 * Knot slopes come from the five-point stencil
 *     s_m = ((f[m-2] - f[m+2]) + 8 (f[m+1] - f[m-1])) / 12
 * (three- and two-point at the ends); interval m holds the Hermite cubic
 *     f(p) = ((c3 p + c4) p + c5) p + c6,  p in [0, 1]
 * and its derivative ((c0 p + c1) p + c2) in units of the table variable.
 */
#ifndef CASCADE_EAM_TABLE_H
#define CASCADE_EAM_TABLE_H

struct eam_spline {
    int n;           /* knots */
    double delta;    /* knot spacing */
    double rdelta;   /* 1 / delta: the lookup multiplies, it does not divide */
    double *c;       /* 7 coefficients per knot: c[7*m + k] */
};

/* Build from n >= 5 knot values; returns 0 or -1 (memory). */
int eam_spline_build(struct eam_spline *s, const double *f, int n, double delta);
void eam_spline_free(struct eam_spline *s);

/* Interval index and fraction of x, clamped to the last interval and
 * to p <= 1 (the table's last value continues flat beyond its end). */
static inline int eam_spline_locate(const struct eam_spline *s, double x, double *p)
{
    double q = x * s->rdelta;
    /* bounds compared in double before the cast: a NaN or huge density
     * must not reach (int) (undefined behaviour) */
    int m = q < (double)(s->n - 2) ? (q > 0 ? (int)q : 0) : s->n - 2;
    /* x < 0 (a negative density): m = 0 extrapolates the first cubic */
    q -= m;
    if (q > 1.0)
        q = 1.0;
    *p = q;
    return m;
}
static inline double eam_spline_value(const struct eam_spline *s, int m, double p)
{
    const double *c = s->c + 7 * m;
    return ((c[3] * p + c[4]) * p + c[5]) * p + c[6];
}
static inline double eam_spline_deriv(const struct eam_spline *s, int m, double p)
{
    const double *c = s->c + 7 * m;
    return (c[0] * p + c[1]) * p + c[2];
}

#endif
