/*
 * meam_spline: the spline-based modified embedded-atom potential of
 * Lenosky et al., Modelling Simul. Mater. Sci. Eng. 8, 825 (2000), read
 * from LAMMPS `meam/spline` files (Debian: Si_1.meam.spline), one element.
 *
 *   E = sum_{i<j} phi(r_ij) + sum_i [U(rho_i) - U(0)]
 *   rho_i = sum_j rho(r_ij) + sum_{j<k} f(r_ij) f(r_ik) g(cos theta_jik)
 *
 * (Lenosky 2000, Eqs. (1)-(2)).  U(0) is subtracted, as LAMMPS does, so an
 * isolated atom has zero energy.  The five functions are clamped cubic
 * splines through the file's knots with the file's end slopes; outside the
 * knots they continue linearly with those slopes (LAMMPS's convention; the
 * third column of each knot line, the second derivative, is recomputed and
 * not read).  The cutoff is the largest last knot of phi, rho and f.
 *
 * File layout (old format): a comment line; then for each of phi, rho, U,
 * f, g: the knot count, the two end slopes, one ignored line, and one line
 * "x y y''" per knot.  The new format has "meam/spline 1 Si" as its second
 * line, a "spline3eq" line before each spline and no ignored line.
 *
 * Full neighbour list.  Pass 1, per owned atom i: its bonds, rho_i, U'(rho_i)
 * and the three-body forces -U'_i d/dx [f f g] on i, j and k.  U' is then
 * copied to the ghosts; pass 2 adds the pair forces
 *   F_i = -sum_j [phi'(r) + (U'_i + U'_j) rho'(r)] (x_i - x_j) / r
 * to atom i only (j's own visit gives j its share).
 */
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "core/parallel.h"
#include "core/textfile.h"
#include "md/potential.h"
#include "md/potential_common.h"

struct mspline {
    int n;
    double *x, *y, *y2;   /* knots and second derivatives */
    double d0, dn;        /* end slopes */
    double h, inv_h;      /* knot spacing when uniform */
    int uniform;
    int last_line;        /* line of the file with the last knot */
};

enum { F_PHI, F_RHO, F_U, F_F, F_G, NFUNC };
static const char *const func_names[NFUNC] = {"phi", "rho", "U", "f", "g"};

struct bond {
    int j;
    double r, u[3];       /* distance and unit vector i -> j */
    double f, fp;         /* f(r), f'(r) */
};

struct meam_spline {
    struct potential base;
    struct mspline s[NFUNC];
    double u0;            /* U(0), the energy of an isolated atom */
    double *up;           /* U'(rho) per owned + ghost atom */
    int cap;
    struct bond *bonds[THREAD_ACCUM_MAX];
    int cap_bonds[THREAD_ACCUM_MAX];
    struct pair_scratch scratch;
};

/* Second derivatives of the clamped cubic spline: the standard tridiagonal
 * system for the knot moments with the end slopes as boundary conditions. */
static int mspline_prepare(struct mspline *s, struct err *e, const char *name)
{
    int n = s->n;
    for (int k = 1; k < n; k++)
        if (!(s->x[k] > s->x[k - 1]))
            return err_set(e, ERR_INPUT, "spline %s: knots must increase (knot %d at %g after %g)",
                           name, k + 1, s->x[k], s->x[k - 1]);
    gsl_vector *diag = gsl_vector_alloc((size_t)n), *off = gsl_vector_alloc((size_t)n - 1),
               *rhs = gsl_vector_alloc((size_t)n), *m = gsl_vector_alloc((size_t)n);
    if (!diag || !off || !rhs || !m) {
        gsl_vector_free(diag); gsl_vector_free(off); gsl_vector_free(rhs); gsl_vector_free(m);
        return err_nomem(e, "spline");
    }
    for (int k = 0; k < n; k++) {
        double hl = k > 0 ? s->x[k] - s->x[k - 1] : 0, hr = k < n - 1 ? s->x[k + 1] - s->x[k] : 0;
        double sl = k > 0 ? (s->y[k] - s->y[k - 1]) / hl : s->d0;
        double sr = k < n - 1 ? (s->y[k + 1] - s->y[k]) / hr : s->dn;
        gsl_vector_set(diag, (size_t)k, (hl + hr) / 3.0);
        gsl_vector_set(rhs, (size_t)k, sr - sl);
        if (k < n - 1)
            gsl_vector_set(off, (size_t)k, hr / 6.0);
    }
    gsl_error_handler_t *old = gsl_set_error_handler_off();
    int st = gsl_linalg_solve_symm_tridiag(diag, off, rhs, m);
    gsl_set_error_handler(old);
    for (int k = 0; k < n && !st; k++)
        s->y2[k] = gsl_vector_get(m, (size_t)k);
    gsl_vector_free(diag); gsl_vector_free(off); gsl_vector_free(rhs); gsl_vector_free(m);
    if (st)
        return err_set(e, ERR_INPUT, "spline %s: singular knot system", name);
    s->h = (s->x[n - 1] - s->x[0]) / (n - 1);
    s->inv_h = 1.0 / s->h;
    s->uniform = 1;
    for (int k = 0; k < n; k++)
        if (fabs(s->x[0] + k * s->h - s->x[k]) > 1e-8)
            s->uniform = 0;
    return 0;
}

/* Value and slope; linear continuation outside the knots. */
static inline double mspline_eval(const struct mspline *s, double x, double *dy)
{
    int n = s->n;
    if (x <= s->x[0]) {
        *dy = s->d0;
        return s->y[0] + s->d0 * (x - s->x[0]);
    }
    if (!(x < s->x[n - 1])) {   /* NaN too: no int cast of it below */
        *dy = s->dn;
        return s->y[n - 1] + s->dn * (x - s->x[n - 1]);
    }
    int k;
    if (s->uniform) {
        k = (int)((x - s->x[0]) * s->inv_h);
        if (k > n - 2)
            k = n - 2;
        /* round-off at a knot: step to the interval that holds x */
        if (x < s->x[k] && k > 0)
            k--;
        else if (x > s->x[k + 1] && k < n - 2)
            k++;
    } else {
        int lo = 0, hi = n - 1;
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (s->x[mid] > x)
                hi = mid;
            else
                lo = mid;
        }
        k = lo;
    }
    double h = s->x[k + 1] - s->x[k];
    double A = (s->x[k + 1] - x) / h, B = 1.0 - A;
    double m0 = s->y2[k], m1 = s->y2[k + 1];
    *dy = (s->y[k + 1] - s->y[k]) / h + ((1.0 - 3.0 * A * A) * m0 + (3.0 * B * B - 1.0) * m1) * h / 6.0;
    return A * s->y[k] + B * s->y[k + 1] + ((A * A * A - A) * m0 + (B * B * B - B) * m1) * h * h / 6.0;
}

static void mspline_free(struct mspline *s)
{
    free(s->x);
    free(s->y);
    free(s->y2);
    memset(s, 0, sizeof *s);
}

static int bonds_reserve(struct meam_spline *m, int tid, int n, struct err *e)
{
    if (n <= m->cap_bonds[tid])
        return 0;
    struct bond *b = realloc(m->bonds[tid], (size_t)n * sizeof *b);
    if (!b)
        return err_nomem(e, "meam/spline bonds");
    m->bonds[tid] = b;
    m->cap_bonds[tid] = n;
    return 0;
}

static int meam_spline_compute(struct potential *pot, struct particles *p, const struct nlist *nl,
                               int flags, struct force_result *out, struct err *e)
{
    struct meam_spline *m = (struct meam_spline *)pot;
    int nt = pot->nthreads < 1 ? 1 : pot->nthreads;
    if (nt > THREAD_ACCUM_MAX)
        nt = THREAD_ACCUM_MAX;
    int ntot = p->n_owned + p->n_ghost;
    if (ntot > m->cap) {
        int cap = ntot + ntot / 4 + 64;
        double *u = realloc(m->up, (size_t)cap * sizeof *u);
        if (!u)
            return err_nomem(e, "meam/spline U'");
        m->up = u;
        m->cap = cap;
    }
    int maxn = 1;
    for (int i = 0; i < p->n_owned; i++)
        if (nl->offset[i + 1] - nl->offset[i] > maxn)
            maxn = nl->offset[i + 1] - nl->offset[i];
    for (int t = 0; t < nt; t++)
        if (bonds_reserve(m, t, maxn, e))
            return ERR_RUNTIME;
    int rc = pair_scratch_begin(&m->scratch, p, flags, nt, e);
    if (rc)
        return rc;
    const double cut = pot->cutoff, cutsq = cut * cut;
    const struct mspline *phi = &m->s[F_PHI], *rho = &m->s[F_RHO], *U = &m->s[F_U],
                         *ff = &m->s[F_F], *gg = &m->s[F_G];
    /* one parallel region: a thread's private force buffer is zeroed when
     * it is handed out, so both passes must write to the same one */
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        struct pair_target t = pair_scratch_target(&m->scratch, p, tid);
        struct bond *bd = m->bonds[tid];
        double esum = 0, w[6] = {0};
        /* pass 1: densities, U', three-body forces */
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            if (i < nl->ilo || i >= nl->ihi) {   /* another MPI rank's slice: no list */
                m->up[i] = 0;
                continue;
            }
            const double *xi = p->x + 3 * i;
            int nb = 0;
            double rho_i = 0, dummy;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double d[3] = {p->x[3 * j] - xi[0], p->x[3 * j + 1] - xi[1], p->x[3 * j + 2] - xi[2]};
                double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if (r2 >= cutsq)
                    continue;
                struct bond *b = &bd[nb];
                b->j = j;
                b->r = sqrt(r2);
                for (int c = 0; c < 3; c++)
                    b->u[c] = d[c] / b->r;
                b->f = mspline_eval(ff, b->r, &b->fp);
                double partial = 0;
                for (int q = 0; q < nb; q++) {   /* Lenosky 2000, Eq. (2): pairs j < k */
                    double cs = b->u[0] * bd[q].u[0] + b->u[1] * bd[q].u[1] + b->u[2] * bd[q].u[2];
                    partial += bd[q].f * mspline_eval(gg, cs, &dummy);
                }
                rho_i += b->f * partial + mspline_eval(rho, b->r, &dummy);
                nb++;
            }
            double up;
            double eu = mspline_eval(U, rho_i, &up) - m->u0;
            m->up[i] = up;
            esum += eu;
            if (t.pe)
                t.pe[i] += eu;
            /* three-body forces: -U'_i grad [f(r_ij) f(r_ik) g(cos theta)] */
            for (int a = 0; a < nb; a++) {
                const struct bond *bj = &bd[a];
                for (int q = 0; q < a; q++) {
                    const struct bond *bk = &bd[q];
                    double cs = bj->u[0] * bk->u[0] + bj->u[1] * bk->u[1] + bj->u[2] * bk->u[2];
                    double gp, g = mspline_eval(gg, cs, &gp);
                    double fj[3], fk[3];
                    for (int c = 0; c < 3; c++) {
                        /* d cos / d x_j = (u_k - cos u_j) / r_ij, and j <-> k */
                        double dcj = (bk->u[c] - cs * bj->u[c]) / bj->r;
                        double dck = (bj->u[c] - cs * bk->u[c]) / bk->r;
                        fj[c] = -up * (bj->fp * bk->f * g * bj->u[c] + bj->f * bk->f * gp * dcj);
                        fk[c] = -up * (bk->fp * bj->f * g * bk->u[c] + bj->f * bk->f * gp * dck);
                    }
                    int j = bj->j, k = bk->j;
                    for (int c = 0; c < 3; c++) {
                        t.f[3 * j + c] += fj[c];
                        t.f[3 * k + c] += fk[c];
                        t.f[3 * i + c] -= fj[c] + fk[c];
                    }
                    double dj[3] = {bj->u[0] * bj->r, bj->u[1] * bj->r, bj->u[2] * bj->r};
                    double dk[3] = {bk->u[0] * bk->r, bk->u[1] * bk->r, bk->u[2] * bk->r};
                    double v[6] = {dj[0] * fj[0] + dk[0] * fk[0], dj[1] * fj[1] + dk[1] * fk[1],
                                   dj[2] * fj[2] + dk[2] * fk[2], dj[0] * fj[1] + dk[0] * fk[1],
                                   dj[0] * fj[2] + dk[0] * fk[2], dj[1] * fj[2] + dk[1] * fk[2]};
                    for (int c = 0; c < 6; c++)
                        w[c] += v[c];
                    if (t.vir) {
                        int who[3] = {i, j, k};
                        for (int s3 = 0; s3 < 3; s3++)
                            for (int c = 0; c < 6; c++)
                                t.vir[6 * who[s3] + c] += v[c] / 3.0;
                    }
                }
            }
        }
#pragma omp single
        {
            /* every rank needs every U'(rho): each computed its own slice */
            parallel_sum(p->par, m->up, (size_t)p->n_owned);
            ghost_forward(p, m->up, 1);
        }
        /* pass 2: pair terms */
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double *xi = p->x + 3 * i;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double d[3] = {xi[0] - p->x[3 * j], xi[1] - p->x[3 * j + 1], xi[2] - p->x[3 * j + 2]};
                double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if (r2 >= cutsq)
                    continue;
                double r = sqrt(r2), dphi, drho;
                double ph = mspline_eval(phi, r, &dphi);
                mspline_eval(rho, r, &drho);
                double fpair = -(dphi + (m->up[i] + m->up[j]) * drho) / r;
                for (int c = 0; c < 3; c++)
                    t.f[3 * i + c] += d[c] * fpair;
                esum += 0.5 * ph;
                pair_tally_virial(w, d[0], d[1], d[2], 0.5 * fpair);
                if (t.pe) {
                    t.pe[i] += 0.5 * ph;
                    double v[6] = {d[0] * d[0], d[1] * d[1], d[2] * d[2],
                                   d[0] * d[1], d[0] * d[2], d[1] * d[2]};
                    for (int c = 0; c < 6; c++)
                        t.vir[6 * i + c] += 0.5 * v[c] * fpair;
                }
            }
        }
        pair_scratch_store_sums(&m->scratch, tid, esum, w);
    }
    pair_scratch_end(&m->scratch, p, out);
    return 0;
}

static void meam_spline_destroy(struct potential *pot)
{
    struct meam_spline *m = (struct meam_spline *)pot;
    for (int k = 0; k < NFUNC; k++)
        mspline_free(&m->s[k]);
    for (int t = 0; t < THREAD_ACCUM_MAX; t++)
        free(m->bonds[t]);
    free(m->up);
    pair_scratch_free(&m->scratch);
    free(m);
}

static const struct potential_ops meam_spline_ops = {"meam/spline", meam_spline_compute,
                                                     meam_spline_destroy};

static int read_spline(struct textfile *t, int newfmt, struct mspline *s, const char *name,
                       struct err *e)
{
    char what[64];
    if (newfmt) {
        const char *kind = textfile_token(t);
        char ex[TEXT_EXCERPT_SIZE];
        if (!kind || strcmp(kind, "spline3eq") != 0)
            return textfile_error(t, e, "spline %s: expected 'spline3eq', found '%s'", name,
                                  kind ? text_excerpt(kind, ex) : "end of file");
    }
    long n;
    snprintf(what, sizeof what, "the knot count of spline %s", name);
    int rc = textfile_int(t, &n, what, e);
    if (rc)
        return rc;
    if (n < 2 || n > 100000)
        return textfile_error(t, e, "spline %s: %ld knots (at least 2 needed)", name, n);
    double d[2];
    snprintf(what, sizeof what, "the end slopes of spline %s", name);
    if ((rc = textfile_doubles(t, d, 2, what, e)))
        return rc;
    s->d0 = d[0];
    s->dn = d[1];
    if (!newfmt) {   /* the ignored "1 0 1 0" line */
        if (textfile_next_line(t) != 0)
            return textfile_error(t, e, "spline %s: unexpected end of file", name);
        t->cursor = t->buf + strlen(t->buf);
    }
    s->n = (int)n;
    s->x = malloc((size_t)n * sizeof *s->x);
    s->y = malloc((size_t)n * sizeof *s->y);
    s->y2 = calloc((size_t)n, sizeof *s->y2);
    if (!s->x || !s->y || !s->y2)
        return err_nomem(e, "spline");
    for (long k = 0; k < n; k++) {
        double v[3];
        snprintf(what, sizeof what, "knot %ld of spline %s", k + 1, name);
        if ((rc = textfile_doubles(t, v, 3, what, e)))
            return rc;
        s->x[k] = v[0];
        s->y[k] = v[1];
    }
    s->last_line = t->line;
    rc = mspline_prepare(s, e, name);
    if (rc == ERR_INPUT)   /* knots out of order: name the place */
        err_prefix(e, "%s:%d: ", t->path, t->line);
    return rc;
}

static int meam_spline_read_file(struct meam_spline *m, const char *path, struct err *e)
{
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    int newfmt = 0;
    if (textfile_next_line(&t) != 0 || textfile_next_line(&t) != 0) {
        rc = textfile_error(&t, e, "file too short");
    } else if (strncmp(t.buf + strspn(t.buf, " \t"), "meam/spline", 11) == 0) {
        newfmt = 1;
        const char *tok = textfile_token(&t);   /* "meam/spline" */
        tok = textfile_token(&t);
        char ex[TEXT_EXCERPT_SIZE];
        if (!tok || strcmp(tok, "1") != 0)
            rc = textfile_error(&t, e, "only one-element meam/spline files are supported "
                                       "(this one has %s)", tok ? text_excerpt(tok, ex) : "none");
        else
            t.cursor = t.buf + strlen(t.buf);   /* the element name follows; skip the line */
    } else {
        t.cursor = t.buf;   /* old format: line 2 is the first knot count */
    }
    for (int k = 0; k < NFUNC && !rc; k++)
        rc = read_spline(&t, newfmt, &m->s[k], func_names[k], e);
    textfile_close(&t);
    return rc;
}

int meam_spline_create(struct cfg_obj *o, struct potential **out)
{
    struct meam_spline *m = calloc(1, sizeof *m);
    if (!m)
        return err_nomem(o->cfg->err, "meam/spline");
    m->base.ops = &meam_spline_ops;
    m->base.list_kind = NLIST_FULL;
    char path[512];
    int rc = potential_file_key(o, path, sizeof path);
    if (!rc)
        rc = potential_read_elements(o, &m->base);
    if (!rc && m->base.nelements != 1) {
        char kp[CFG_PATH_MAX];
        snprintf(kp, sizeof kp, "%s.elements", o->path);
        rc = cfg_error_at(o->cfg, kp, "meam/spline supports one element, %d given",
                          m->base.nelements);
    }
    if (rc || o->cfg->shallow) {
        meam_spline_destroy(&m->base);
        return rc;
    }
    if ((rc = meam_spline_read_file(m, path, o->cfg->err))) {
        char msg[ERR_MSG_MAX], kp[CFG_PATH_MAX];
        snprintf(msg, sizeof msg, "%s", o->cfg->err->msg);
        snprintf(kp, sizeof kp, "%s.file", o->path);
        rc = cfg_error_at(o->cfg, kp, "corrupt or unreadable meam/spline file: %s", msg);
        meam_spline_destroy(&m->base);
        return rc;
    }
    double d;
    m->u0 = mspline_eval(&m->s[F_U], 0.0, &d);
    double cut = 0;
    const int radial[3] = {F_PHI, F_RHO, F_F};
    for (int k = 0; k < 3; k++) {
        const struct mspline *s = &m->s[radial[k]];
        if (s->x[s->n - 1] > cut) {
            cut = s->x[s->n - 1];
            snprintf(m->base.cutoff_source, sizeof m->base.cutoff_source,
                     "%s:%d (last knot of %s)", path, s->last_line, func_names[radial[k]]);
        }
    }
    m->base.cutoff = cut;
    snprintf(m->base.description, sizeof m->base.description,
             "spline MEAM (Lenosky 2000) from %s, cutoff %g Å", path, cut);
    snprintf(m->base.source_path, sizeof m->base.source_path, "%s", path);
    *out = &m->base;
    return 0;
}
