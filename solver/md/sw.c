/*
 * sw: Stillinger-Weber three-body potential (Phys. Rev. B 31, 5262 (1985))
 * read from LAMMPS *.sw files (entries: e1 e2 e3 epsilon sigma a lambda
 * gamma costheta0 A B p q tol).
 *
 *   E = sum_{i<j} phi2(r_ij) + sum_i sum_{j<k} phi3(r_ij, r_ik, theta_jik)
 *   phi2 = A eps [B (sigma/r)^p - (sigma/r)^q] exp(sigma / (r - a sigma))
 *   phi3 = lambda eps (cos theta - cos theta0)^2
 *          exp(gamma_ij sigma_ij / (r_ij - a_ij sigma_ij))
 *          exp(gamma_ik sigma_ik / (r_ik - a_ik sigma_ik))
 *
 * A full neighbour list: each owned atom takes half of each pair's energy
 * and its own pair force; the three-body terms centred on it push on both
 * neighbours (ghost forces are added back to the owners by the caller).
 * Parameters of the ij leg come from entry (i, j, j), lambda and cos theta0
 * from (i, j, k), as in LAMMPS.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/textfile.h"
#include "md/potential.h"
#include "md/potential_common.h"

#define NE PARTICLES_MAX_TYPES

struct sw_entry {
    double eps, sigma, a, lambda, gamma, cos0, A, B, p, q;
    int p_int, q_int;     /* p, q when small non-negative integers, else -1 */
    double cut, cutsq;
    int set;
    int line;             /* of the file: where sigma is */
};

struct sw_near;

struct sw {
    struct potential base;
    struct sw_entry e[NE][NE][NE];
    struct pair_scratch scratch;
    struct sw_near *near;   /* per thread: maxnb near neighbours of one atom */
    size_t cap_near;
    int maxnb;
};

/* x^n for a small non-negative integer n by multiplication (p and q of
 * the common files are 4 and 0: pow() would cost more than the rest of
 * the pair). */
static inline double sw_ipow(double x, int n)
{
    double r = 1.0;
    for (; n > 0; n--)
        r *= x;
    return r;
}

static void sw_two_body(const struct sw_entry *P, double r, double rinv, double *phi,
                        double *dphi)
{
    double sr = P->sigma * rinv;
    double srp = P->p_int >= 0 ? sw_ipow(sr, P->p_int) : pow(sr, P->p);
    double srq = P->q_int >= 0 ? sw_ipow(sr, P->q_int) : pow(sr, P->q);
    double den = r - P->a * P->sigma;
    double ex = exp(P->sigma / den);
    double poly = P->B * srp - srq;
    *phi = P->A * P->eps * poly * ex;
    /* d/dr: poly' = (-p B srp + q srq) / r ; ex' = -sigma / den^2 ex */
    double dpoly = (-P->p * P->B * srp + P->q * srq) * rinv;
    *dphi = P->A * P->eps * (dpoly - poly * P->sigma / (den * den)) * ex;
}

/* A neighbour of the centre atom closer than their pair cutoff, with what
 * both the two-body and every three-body term of the centre need. */
struct sw_near {
    int j, tj;
    const struct sw_entry *P;   /* e[ti][tj][tj]: the ij leg */
    double d[3];                /* x_j - x_i */
    double rinv, rinvsq;
    double e, de;               /* exp(gamma sigma / (r - a sigma)) and d/dr of it */
};

/* Per-thread room for the near neighbours of one atom (the longest list). */
static int sw_reserve_near(struct sw *s, const struct nlist *nl, int nt, struct err *e)
{
    int maxnb = 1;
    for (int i = 0; i < nl->n; i++)
        if (nl->offset[i + 1] - nl->offset[i] > maxnb)
            maxnb = nl->offset[i + 1] - nl->offset[i];
    s->maxnb = maxnb;
    size_t need = (size_t)nt * maxnb;
    if (need <= s->cap_near)
        return 0;
    size_t cap = need + need / 4;
    struct sw_near *nn = realloc(s->near, cap * sizeof *nn);
    if (!nn)
        return err_nomem(e, "Stillinger-Weber neighbours");
    s->near = nn;
    s->cap_near = cap;
    return 0;
}

/* Each atom's list (cutoff + skin) holds several times more atoms than its
 * pair cutoff (diamond Si: 4 within 3.77 Å of about 30 listed), and the
 * three-body sum runs over pairs of them: the near ones are gathered first,
 * with their distances and exponential factors, and both sums run over
 * those only, in list order (the same terms in the same order as over the
 * whole list). */
static int sw_compute(struct potential *pot, struct particles *p, const struct nlist *nl, int flags,
                      struct force_result *out, struct err *e)
{
    struct sw *s = (struct sw *)pot;
    int nt = pot->nthreads < 1 ? 1 : pot->nthreads;
    int rc = pair_scratch_begin(&s->scratch, p, flags, nt, e);
    if (!rc)
        rc = sw_reserve_near(s, nl, nt, e);
    if (rc)
        return rc;
    const int *tmap = pot->type_map;
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        struct pair_target t = pair_scratch_target(&s->scratch, p, tid);
        struct sw_near *near = s->near + (size_t)tid * s->maxnb;
        double esum = 0, w[6] = {0};
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double *xi = p->x + 3 * i;
            int ti = tmap[p->type[i]];
            int nn = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                int tj = tmap[p->type[j]];
                const struct sw_entry *P = &s->e[ti][tj][tj];
                double d[3] = {p->x[3 * j] - xi[0], p->x[3 * j + 1] - xi[1], p->x[3 * j + 2] - xi[2]};
                double rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if (rsq >= P->cutsq)
                    continue;
                struct sw_near *a = &near[nn++];
                a->j = j;
                a->tj = tj;
                a->P = P;
                for (int c = 0; c < 3; c++)
                    a->d[c] = d[c];
                double r = sqrt(rsq);
                a->rinv = 1.0 / r;
                a->rinvsq = 1.0 / rsq;
                double den = r - P->a * P->sigma;
                double g = P->gamma * P->sigma / den;
                a->e = exp(g);
                a->de = -g / den * a->e;   /* d e / d r */
                /* two-body: half of the pair, the whole pair force on i
                 * (j's own loop gives j its share); energy and virial are
                 * split between the two loops */
                double phi, dphi;
                sw_two_body(P, r, a->rinv, &phi, &dphi);
                double fpair = dphi * a->rinv;   /* along d = x_j - x_i */
                for (int c = 0; c < 3; c++)
                    t.f[3 * i + c] += d[c] * fpair;
                esum += 0.5 * phi;
                pair_tally_virial(w, d[0], d[1], d[2], -0.5 * fpair);
                if (t.pe) {
                    t.pe[i] += 0.5 * phi;
                    double v[6] = {d[0] * d[0], d[1] * d[1], d[2] * d[2],
                                   d[0] * d[1], d[0] * d[2], d[1] * d[2]};
                    for (int c = 0; c < 6; c++)
                        t.vir[6 * i + c] -= 0.5 * v[c] * fpair;
                }
            }
            /* three-body terms centred on i: with c = cos theta_jik,
             *   dc/dd1 = d2 / (r1 r2) - c d1 / r1^2  (and 1 <-> 2),
             * so F_j = -dE/dd1 = d1 (-E_r1 / r1 + E_c c / r1^2) - d2 E_c / (r1 r2) */
            for (int n1 = 0; n1 < nn; n1++) {
                const struct sw_near *a = &near[n1];
                const int j = a->j;
                const double *d1 = a->d;
                const double rinv1 = a->rinv, rinvsq1 = a->rinvsq, e1 = a->e, de1 = a->de;
                for (int n2 = n1 + 1; n2 < nn; n2++) {
                    const struct sw_near *b = &near[n2];
                    const int k = b->j;
                    const double *d2 = b->d;
                    const double rinv2 = b->rinv, rinvsq2 = b->rinvsq, e2 = b->e, de2 = b->de;
                    const struct sw_entry *Pijk = &s->e[ti][a->tj][b->tj];
                    double rinv12 = rinv1 * rinv2;
                    double cs = (d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2]) * rinv12;
                    double dc = cs - Pijk->cos0;
                    double le = Pijk->lambda * Pijk->eps;
                    double ee = e1 * e2;
                    double E3 = le * dc * dc * ee;
                    double dEdc = 2.0 * le * dc * ee;
                    double dEdr1 = le * dc * dc * de1 * e2;
                    double dEdr2 = le * dc * dc * e1 * de2;
                    double csc = dEdc * cs;
                    double a1 = -dEdr1 * rinv1 + csc * rinvsq1;
                    double a2 = -dEdr2 * rinv2 + csc * rinvsq2;
                    double b12 = dEdc * rinv12;
                    double fj[3], fk[3];
                    for (int c = 0; c < 3; c++) {
                        fj[c] = d1[c] * a1 - d2[c] * b12;
                        fk[c] = d2[c] * a2 - d1[c] * b12;
                    }
                    for (int c = 0; c < 3; c++) {
                        t.f[3 * j + c] += fj[c];
                        t.f[3 * k + c] += fk[c];
                        t.f[3 * i + c] -= fj[c] + fk[c];
                    }
                    esum += E3;
                    double v[6] = {d1[0] * fj[0] + d2[0] * fk[0], d1[1] * fj[1] + d2[1] * fk[1],
                                   d1[2] * fj[2] + d2[2] * fk[2], d1[0] * fj[1] + d2[0] * fk[1],
                                   d1[0] * fj[2] + d2[0] * fk[2], d1[1] * fj[2] + d2[1] * fk[2]};
                    for (int c = 0; c < 6; c++)
                        w[c] += v[c];
                    if (t.pe) {
                        int who[3] = {i, j, k};
                        for (int q = 0; q < 3; q++) {
                            t.pe[who[q]] += E3 / 3.0;
                            for (int c = 0; c < 6; c++)
                                t.vir[6 * who[q] + c] += v[c] / 3.0;
                        }
                    }
                }
            }
        }
        pair_scratch_store_sums(&s->scratch, tid, esum, w);
    }
    pair_scratch_end(&s->scratch, p, out);
    return 0;
}

static void sw_destroy(struct potential *pot)
{
    struct sw *s = (struct sw *)pot;
    pair_scratch_free(&s->scratch);
    free(s->near);
    free(s);
}

static const struct potential_ops sw_ops = {"sw", sw_compute, sw_destroy};

/* The 14 fields of an entry, for messages. */
static const char *const sw_fields[14] = {"element 1", "element 2", "element 3", "epsilon",
                                          "sigma", "a", "lambda", "gamma", "costheta0", "A",
                                          "B", "p", "q", "tol"};

static int sw_read_file(struct sw *s, const char *path, struct err *e)
{
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    t.strip_comments = 1;
    int entry_line[NE][NE][NE] = {{{0}}};
    for (;;) {
        /* an entry is 14 fields, possibly spread over several lines; each
         * field's line is kept for messages */
        char tok[14][64];
        int line[14];
        int ntok = 0;
        const char *s1;
        char ex[TEXT_EXCERPT_SIZE];
        while (ntok < 14 && (s1 = textfile_token(&t)) != NULL) {
            line[ntok] = t.line;
            if (strlen(s1) >= sizeof tok[0]) {
                /* cut to fit it would be another number (or element) */
                rc = textfile_error(&t, e, "field %d (%s): '%s' is longer than %zu characters",
                                    ntok + 1, sw_fields[ntok], text_excerpt(s1, ex),
                                    sizeof tok[0] - 1);
                textfile_close(&t);
                return rc;
            }
            snprintf(tok[ntok++], sizeof tok[0], "%s", s1);
        }
        if (ntok == 0)
            break;
        if (ntok < 14) {
            rc = textfile_error(&t, e, "incomplete Stillinger-Weber entry: 14 fields needed, %d found",
                                ntok);
            textfile_close(&t);
            return rc;
        }
        int idx[3];
        for (int k = 0; k < 3; k++) {
            idx[k] = -1;
            for (int a = 0; a < s->base.nelements; a++)
                if (strcmp(s->base.element[a], tok[k]) == 0)
                    idx[k] = a;
        }
        double v[11];
        for (int k = 0; k < 11; k++) {
            if (text_parse_real(tok[3 + k], &v[k]) != 0) {
                rc = textfile_error_at(&t, line[3 + k], e,
                                       "field %d (%s): '%s' is not a finite decimal number",
                                       4 + k, sw_fields[3 + k], text_excerpt(tok[3 + k], ex));
                textfile_close(&t);
                return rc;
            }
            /* LAMMPS's rule: every parameter but cos theta0 is >= 0.  A
             * zero sigma or a is legal: mixed entries (i j k, j != k) give
             * only lambda, epsilon and cos theta0 to the three-body term, and
             * GaN.sw and CdTe.sw write 0 for their radial parameters; an
             * i j j entry with a * sigma = 0 means no pair interaction (the
             * potential as a whole must have a range: checked below) */
            if (k != 5 && !(v[k] >= 0)) {
                rc = textfile_error_at(&t, line[3 + k], e, "field %d (%s) must be >= 0, found %g",
                                       4 + k, sw_fields[3 + k], v[k]);
                textfile_close(&t);
                return rc;
            }
        }
        if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0)
            continue;   /* an entry for elements not in use */
        int *seen = &entry_line[idx[0]][idx[1]][idx[2]];
        if (*seen) {
            rc = textfile_error_at(&t, line[0], e, "second entry for %s %s %s (the first is at "
                                   "line %d)", tok[0], tok[1], tok[2], *seen);
            textfile_close(&t);
            return rc;
        }
        *seen = line[0];
        struct sw_entry *P = &s->e[idx[0]][idx[1]][idx[2]];
        P->eps = v[0]; P->sigma = v[1]; P->a = v[2]; P->lambda = v[3]; P->gamma = v[4];
        P->cos0 = v[5]; P->A = v[6]; P->B = v[7]; P->p = v[8]; P->q = v[9];
        P->cut = P->a * P->sigma;
        P->cutsq = P->cut * P->cut;
        P->p_int = P->p == floor(P->p) && P->p <= 16 ? (int)P->p : -1;   /* p, q >= 0 checked above */
        P->q_int = P->q == floor(P->q) && P->q <= 16 ? (int)P->q : -1;
        P->line = line[4];
        P->set = 1;
    }
    textfile_close(&t);
    int ne = s->base.nelements;
    for (int a = 0; a < ne; a++)
        for (int b = 0; b < ne; b++)
            for (int c = 0; c < ne; c++)
                if (!s->e[a][b][c].set)
                    return err_set(e, ERR_INPUT, "%s: no entry for the triplet %s %s %s", path,
                                   s->base.element[a], s->base.element[b], s->base.element[c]);
    return 0;
}

int sw_create(struct cfg_obj *o, struct potential **out)
{
    struct sw *s = calloc(1, sizeof *s);
    if (!s)
        return err_nomem(o->cfg->err, "sw");
    s->base.ops = &sw_ops;
    s->base.list_kind = NLIST_FULL;
    char path[512];
    int rc = potential_file_key(o, path, sizeof path);
    if (!rc)
        rc = potential_read_elements(o, &s->base);
    if (rc || o->cfg->shallow) {
        free(s);
        return rc;
    }
    if ((rc = sw_read_file(s, path, o->cfg->err))) {
        char msg[ERR_MSG_MAX], kp[CFG_PATH_MAX];
        snprintf(msg, sizeof msg, "%s", o->cfg->err->msg);
        snprintf(kp, sizeof kp, "%s.file", o->path);
        rc = cfg_error_at(o->cfg, kp, "corrupt or unreadable Stillinger-Weber file: %s", msg);
    }
    if (rc) {
        free(s);
        return rc;
    }
    double cut = 0;
    int ne = s->base.nelements;
    for (int a = 0; a < ne; a++)
        for (int b = 0; b < ne; b++)
            if (s->e[a][b][b].cut > cut) {
                cut = s->e[a][b][b].cut;
                snprintf(s->base.cutoff_source, sizeof s->base.cutoff_source,
                         "%s:%d (a * sigma of %s %s %s)", path, s->e[a][b][b].line,
                         s->base.element[a], s->base.element[b], s->base.element[b]);
            }
    if (!(cut > 0)) {
        char kp[CFG_PATH_MAX];
        snprintf(kp, sizeof kp, "%s.file", o->path);
        free(s);
        return cfg_error_at(o->cfg, kp,
                            "Stillinger-Weber file %s: no pair of the elements in use interacts "
                            "(a * sigma is 0 in every i j j entry)",
                            path);
    }
    s->base.cutoff = cut;
    snprintf(s->base.description, sizeof s->base.description,
             "Stillinger-Weber from %s, cutoff %g Å", path, cut);
    snprintf(s->base.source_path, sizeof s->base.source_path, "%s", path);
    *out = &s->base;
    return 0;
}
