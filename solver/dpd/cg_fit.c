/* cg_fit: GSL nonlinear least squares of the coarse-grained parameters. */
#include "dpd/cg_fit.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "dpd/cg_lattice.h"

const char *const cg_fit_param_names[CG_FIT_NPAR + 1] = {"epsilon", "c", "n", "m", "a", NULL};

static const double GCM3_PER_AMU_A3 = UNITS_AMU_A3_TO_KG_M3 / 1000.0;

double cg_fit_lattice_constant(double mass, double density)
{
    return cbrt(4.0 * mass * GCM3_PER_AMU_A3 / density);
}

double cg_fit_model_pressure(const struct sc_params *sc, double mass, double T, int thermal,
                             double density)
{
    double aL = cg_fit_lattice_constant(mass, density);
    return cg_lattice_pressure(sc, aL, T, thermal) * UNITS_EVA3_TO_GPA;
}

struct fit_ctx {
    const struct cg_fit_spec *spec;
    const struct cg_fit_point *pts;
    int npts;
    int map[CG_FIT_NPAR];   /* free parameter k is sc field map[k] */
    int nfree;
};

static double *param_slot(struct sc_params *sc, int which)
{
    switch (which) {
    case CG_FIT_EPS: return &sc->eps;
    case CG_FIT_C: return &sc->c;
    case CG_FIT_N: return &sc->n;
    case CG_FIT_M: return &sc->m;
    default: return &sc->a;
    }
}

static void unpack(const struct fit_ctx *ctx, const gsl_vector *x, struct sc_params *sc)
{
    *sc = ctx->spec->start;
    for (int k = 0; k < ctx->nfree; k++)
        *param_slot(sc, ctx->map[k]) = exp(gsl_vector_get(x, (size_t)k));
    sc_params_finish(sc);
}

static double point_scale(const struct fit_ctx *ctx, int i)
{
    double s = ctx->pts[i].sigma;
    return ctx->spec->weighted && s > 0 ? s : 1.0;
}

static int residuals(const gsl_vector *x, void *data, gsl_vector *f)
{
    const struct fit_ctx *ctx = data;
    struct sc_params sc;
    unpack(ctx, x, &sc);
    /* keep the form physical: n > m and a bound crystal */
    int bad = !(sc.n > sc.m);
    for (int i = 0; i < ctx->npts; i++) {
        double P = bad ? 1e6
                       : cg_fit_model_pressure(&sc, ctx->spec->mass, ctx->spec->temperature,
                                               ctx->spec->thermal, ctx->pts[i].density);
        if (!isfinite(P))
            P = 1e6;
        gsl_vector_set(f, (size_t)i, (P - ctx->pts[i].pressure) / point_scale(ctx, i));
    }
    return GSL_SUCCESS;
}

int cg_fit_isotherm(const struct cg_fit_spec *spec, const struct cg_fit_point *pts, int npts,
                    struct cg_fit_result *res, struct err *e)
{
    memset(res, 0, sizeof *res);
    struct fit_ctx ctx = {spec, pts, npts, {0}, 0};
    for (int k = 0; k < CG_FIT_NPAR; k++)
        if (spec->free[k])
            ctx.map[ctx.nfree++] = k;
    if (ctx.nfree == 0)
        return err_set(e, ERR_INPUT, "no parameter is free to fit");
    if (npts < ctx.nfree)
        return err_set(e, ERR_INPUT, "%d isotherm points cannot determine %d parameters", npts,
                       ctx.nfree);
    if (spec->free[CG_FIT_C] && spec->free[CG_FIT_A])
        return err_set(e, ERR_INPUT, "c and a cannot both be fitted: both only set the "
                                     "equilibrium lattice constant");
    gsl_set_error_handler_off();
    gsl_multifit_nlinear_fdf fdf;
    memset(&fdf, 0, sizeof fdf);
    fdf.f = residuals;
    fdf.df = NULL;   /* forward-difference Jacobian */
    fdf.n = (size_t)npts;
    fdf.p = (size_t)ctx.nfree;
    fdf.params = &ctx;
    gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
    fp.scale = gsl_multifit_nlinear_scale_more;
    gsl_multifit_nlinear_workspace *w =
        gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)npts, (size_t)ctx.nfree);
    gsl_vector *x = gsl_vector_alloc((size_t)ctx.nfree);
    gsl_matrix *covar = gsl_matrix_alloc((size_t)ctx.nfree, (size_t)ctx.nfree);
    if (!w || !x || !covar) {
        if (w)
            gsl_multifit_nlinear_free(w);
        gsl_vector_free(x);
        gsl_matrix_free(covar);
        return err_nomem(e, "isotherm fit");
    }
    struct sc_params start = spec->start;
    for (int k = 0; k < ctx.nfree; k++)
        gsl_vector_set(x, (size_t)k, log(*param_slot(&start, ctx.map[k])));
    int info = 0;
    int status = gsl_multifit_nlinear_init(x, &fdf, w);
    if (status == GSL_SUCCESS)
        status = gsl_multifit_nlinear_driver((size_t)(spec->max_iter > 0 ? spec->max_iter : 500),
                                             1e-12, 1e-12, 1e-14, NULL, NULL, &info, w);
    int rc = 0;
    if (status != GSL_SUCCESS && status != GSL_EMAXITER) {
        rc = err_set(e, ERR_RUNTIME, "isotherm fit failed: %s", gsl_strerror(status));
    } else {
        res->stop = status == GSL_EMAXITER ? "iteration limit"
                    : info == 1            ? "small step"
                    : info == 2            ? "small gradient"
                                           : "converged";
        res->iterations = (long)gsl_multifit_nlinear_niter(w);
        unpack(&ctx, w->x, &res->sc);
        gsl_vector *f = gsl_multifit_nlinear_residual(w);
        double chi2 = 0, ss = 0, mx = 0;
        for (int i = 0; i < npts; i++) {
            double r = gsl_vector_get(f, (size_t)i);
            double rp = r * point_scale(&ctx, i);   /* GPa */
            chi2 += r * r;
            ss += rp * rp;
            if (fabs(rp) > mx)
                mx = fabs(rp);
        }
        res->chi2 = chi2;
        res->rms = sqrt(ss / npts);
        res->max_abs = mx;
        /* standard errors: covariance of the log-parameters scaled by the
         * residual variance, propagated to the parameters (d p = p d ln p) */
        gsl_matrix *J = gsl_multifit_nlinear_jac(w);
        gsl_multifit_nlinear_covar(J, 0.0, covar);
        int dof = npts - ctx.nfree;
        double s2 = dof > 0 ? chi2 / dof : 0;
        for (int k = 0; k < ctx.nfree; k++) {
            double var = gsl_matrix_get(covar, (size_t)k, (size_t)k) * s2;
            double pk = *param_slot(&res->sc, ctx.map[k]);
            res->stderr_par[ctx.map[k]] = var > 0 ? pk * sqrt(var) : 0;
        }
    }
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x);
    gsl_matrix_free(covar);
    return rc;
}
