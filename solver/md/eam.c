/*
 * eam: embedded-atom method forces (Daw & Baskes), LAMMPS-compatible tables.
 *
 *   E = sum_i F_i(rho_i) + 1/2 sum_{i!=j} phi_ij(r_ij),  rho_i = sum_j rho_j(r_ij)
 *
 * Two passes over the half list: densities (ghost densities added back to
 * their owners), then F'(rho) sent to the ghosts and the pair forces
 *   f_ij = -[F'_i rho'_j(r) + F'_j rho'_i(r) + phi'(r)] (r_ij / r).
 * F(rho) continues linearly beyond the table (as LAMMPS) so that a close
 * approach of two atoms conserves energy.
 *
 * Case keys: style (eam | eam/alloy | eam/fs), file, elements (eam/alloy and
 * eam/fs: the file's elements to use, default all; eam: default from Z).
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "md/eam_file.h"
#include "md/eam_table.h"
#include "md/potential.h"
#include "md/potential_common.h"

#define NE PARTICLES_MAX_TYPES

struct eam {
    struct potential base;
    int ne;
    double rhomax, cutsq;
    struct eam_spline frho[NE];
    struct eam_spline rhor_store[NE * NE];
    struct eam_spline z2r_store[NE * NE];
    const struct eam_spline *rhor[NE][NE];   /* [a][b]: density at a b-atom from an a-atom */
    const struct eam_spline *z2r[NE][NE];    /* symmetric */
    int sel[NE];                             /* selected element -> file element */
    /* one element: the value cubics of rho(r) and r phi(r) per knot, 8
     * doubles = one 64-byte cache line (derivatives follow from the value
     * coefficients), so a pair touches one line and the table is half the
     * size of two 7-coefficient tables */
    double *tab1;
    int nr1;
    double rdr1;
    double *rho, *fp;
    int *ninner;     /* per owned atom: neighbours within the cutoff, moved to
                      * the front of its list by the density pass */
    int cap;
    double *pairbuf;     /* one-element density pass: per-thread scratch */
    int *jbuf;
    size_t cap_pairbuf;
    int maxnb;
    struct thread_accum rho_acc;
    struct pair_scratch scratch;
    double esum_embed[THREAD_ACCUM_MAX];
};

static int eam_reserve(struct eam *m, int n, struct err *e)
{
    if (n <= m->cap)
        return 0;
    int cap = n + n / 4 + 64;
    double *r = realloc(m->rho, (size_t)cap * sizeof *r);
    if (r)
        m->rho = r;
    double *f = realloc(m->fp, (size_t)cap * sizeof *f);
    if (f)
        m->fp = f;
    int *ni = realloc(m->ninner, (size_t)cap * sizeof *ni);
    if (ni)
        m->ninner = ni;
    if (!r || !f || !ni)
        return err_nomem(e, "EAM densities");
    m->cap = cap;
    return 0;
}

/* Embedding energies and F'(rho) of the owned atoms; beyond the table F
 * continues linearly (as LAMMPS), so a close approach conserves energy. */
static double eam_embed(struct eam *m, struct particles *p, const struct nlist *nl, int flags)
{
    const int *tmap = m->base.type_map;
    double embed = 0;
    for (int i = 0; i < p->n_owned; i++) {
        const struct eam_spline *F = &m->frho[m->sel[tmap[p->type[i]]]];
        double q;
        int im = eam_spline_locate(F, m->rho[i], &q);
        m->fp[i] = eam_spline_deriv(F, im, q);
        double phi = eam_spline_value(F, im, q);
        if (m->rho[i] > m->rhomax)
            phi += m->fp[i] * (m->rho[i] - m->rhomax);
        /* every rank knows every F'(rho); the energy belongs to one slice */
        if (i < nl->ilo || i >= nl->ihi)
            continue;
        embed += phi;
        if (flags & POT_PERATOM)
            p->pe[i] = phi;
    }
    return embed;
}

/* One pair of the one-element kernel: the cubic row of r (rho(r) in
 * c[0..3], r phi(r) in c[4..7]); returns the pair force over r and
 * phi(r).  Inlined into the vectorised and the per-atom-tally loops alike, so
 * both do the same arithmetic. */
struct eam_pair {
    double fpair, phi;
};
static inline struct eam_pair eam_one_pair(const double *restrict tab, double rdr, int kmax,
                                           double r, double fpsum)
{
    double q = r * rdr;
    /* r is below the cutoff (the density pass kept only such pairs, and a
     * NaN distance fails that test), so q is finite and small and the cast
     * is defined; the clamp is on the int, without a branch, so the loop
     * vectorises */
    int im = (int)q;
    im = im < kmax ? im : kmax;
    q -= im;
    q = q > 1.0 ? 1.0 : q;
    /* one int index for all eight loads: a vector gather each */
    const int b = 8 * im;
    /* d/dr of ((a q + b) q + c) q + d, q = r / dr */
    double rhop = ((3.0 * tab[b] * q + 2.0 * tab[b + 1]) * q + tab[b + 2]) * rdr;
    double z2p = ((3.0 * tab[b + 4] * q + 2.0 * tab[b + 5]) * q + tab[b + 6]) * rdr;
    double z2 = ((tab[b + 4] * q + tab[b + 5]) * q + tab[b + 6]) * q + tab[b + 7];
    double recip = 1.0 / r;
    double phi = z2 * recip;
    double phip = z2p * recip - phi * recip;
    return (struct eam_pair){-(fpsum * rhop + phip) * recip, phi};
}

/* The one-element kernel (the common case): the same density function both
 * ways, so rho'_i = rho'_j, and one interleaved table row per pair.
 *
 * Both passes are written for the vector unit: within one atom's half list
 * every neighbour j appears once, so the scattered updates rho[j] and f[j]
 * of one atom's loop never collide and `omp simd` is safe.  The density
 * pass first computes all squared distances of an atom's list (a gather
 * loop), then moves the neighbours within the cutoff to the front without
 * branches (two cursors), then evaluates the density cubic on those only. */
static int eam_compute_one(struct eam *m, struct particles *p, const struct nlist *nl, int flags,
                           struct force_result *out, struct err *e)
{
    int nt = m->base.nthreads < 1 ? 1 : m->base.nthreads;
    int ntot = p->n_owned + p->n_ghost;
    const double cutsq = m->cutsq, rdr = m->rdr1;
    const int kmax = m->nr1 - 2;
    const double *restrict tab = m->tab1;
    const double *restrict x = p->x;
    const int *restrict off = nl->offset;
    /* The density pass partitions each atom's neighbours: those within the
     * cutoff first (a reordering, the set is unchanged), so the force pass
     * visits only interacting pairs. */
    int *restrict nb = nl->neigh;
    int *restrict ninner = m->ninner;
    const int maxnb = m->maxnb;
    memset(m->rho, 0, (size_t)ntot * sizeof(double));

    /* firstprivate: loop constants become thread-locals the compiler keeps
     * in registers (shared ones would be reloaded after every store) */
#pragma omp parallel num_threads(nt) firstprivate(cutsq, rdr, kmax, tab, x, off, nb, ninner, ntot, maxnb)
    {
        int tid = omp_get_thread_num();
        double *restrict rho = thread_accum_target(&m->rho_acc, tid, m->rho, (size_t)ntot);
        /* per-thread scratch: squared distances, then the inner ones' r;
         * the outer neighbours' indices wait in jout */
        double *restrict r2s = m->pairbuf + (size_t)tid * 2 * maxnb;
        double *restrict rin = r2s + maxnb;
        int *restrict jout = m->jbuf + (size_t)tid * maxnb;
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
            int *restrict nbi = nb + off[i];
            const int len = off[i + 1] - off[i];
#pragma omp simd
            for (int k = 0; k < len; k++) {
                int j = nbi[k];
                double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
                r2s[k] = dx * dx + dy * dy + dz * dz;
            }
            int nin = 0, nout = 0;
            for (int k = 0; k < len; k++) {
                int j = nbi[k];
                int in = r2s[k] < cutsq;   /* a NaN distance counts as outside */
                nbi[nin] = j;              /* nin <= k: never overwrites an unread entry */
                rin[nin] = r2s[k];
                jout[nout] = j;
                nin += in;
                nout += 1 - in;
            }
            memcpy(nbi + nin, jout, (size_t)nout * sizeof(int));
            double rhoi = 0;
#pragma omp simd reduction(+ : rhoi)
            for (int k = 0; k < nin; k++) {
                double q = sqrt(rin[k]) * rdr;
                int im = (int)q;   /* r < cutoff: as in eam_one_pair */
                im = im < kmax ? im : kmax;
                q -= im;
                q = q > 1.0 ? 1.0 : q;
                const int b = 8 * im;
                double v = ((tab[b] * q + tab[b + 1]) * q + tab[b + 2]) * q + tab[b + 3];
                rhoi += v;
                rho[nbi[k]] += v;
            }
            rho[i] += rhoi;
            ninner[i] = nin;
        }
    }
    thread_accum_reduce(&m->rho_acc, m->rho, (size_t)ntot);
    ghost_reverse_add(p, m->rho, 1);
    double embed = eam_embed(m, p, nl, flags);
    ghost_forward(p, m->fp, 1);

    const double *restrict fp = m->fp;
#pragma omp parallel num_threads(nt) firstprivate(rdr, kmax, tab, x, off, nb, ninner, fp)
    {
        int tid = omp_get_thread_num();
        struct pair_target t = pair_scratch_target(&m->scratch, p, tid);
        double *restrict f = t.f;
        double esum = 0;
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
            const double fpi = fp[i];
            const int *restrict nbi = nb + off[i];
            const int nin = ninner[i];
            double fxi = 0, fyi = 0, fzi = 0;
            if (!t.pe) {
#pragma omp simd reduction(+ : fxi, fyi, fzi, esum)
                for (int k = 0; k < nin; k++) {
                    int j = nbi[k];
                    double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
                    struct eam_pair pr = eam_one_pair(tab, rdr, kmax,
                                                      sqrt(dx * dx + dy * dy + dz * dz), fpi + fp[j]);
                    double fpair = pr.fpair, phi = pr.phi;
                    fxi += dx * fpair;
                    fyi += dy * fpair;
                    fzi += dz * fpair;
                    f[3 * j] -= dx * fpair;
                    f[3 * j + 1] -= dy * fpair;
                    f[3 * j + 2] -= dz * fpair;
                    esum += phi;
                }
            } else {
                for (int k = 0; k < nin; k++) {
                    int j = nbi[k];
                    double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
                    struct eam_pair pr = eam_one_pair(tab, rdr, kmax,
                                                      sqrt(dx * dx + dy * dy + dz * dz), fpi + fp[j]);
                    double fpair = pr.fpair, phi = pr.phi;
                    fxi += dx * fpair;
                    fyi += dy * fpair;
                    fzi += dz * fpair;
                    f[3 * j] -= dx * fpair;
                    f[3 * j + 1] -= dy * fpair;
                    f[3 * j + 2] -= dz * fpair;
                    esum += phi;
                    pair_tally_peratom(&t, i, j, phi, dx, dy, dz, fpair);
                }
            }
            f[3 * i] += fxi;
            f[3 * i + 1] += fyi;
            f[3 * i + 2] += fzi;
        }
        const double w[6] = {0, 0, 0, 0, 0, 0};
        pair_scratch_store_sums(&m->scratch, tid, esum, w);
    }
    pair_scratch_end(&m->scratch, p, out);
    /* virial from the forces on owned and ghost atoms (before they are
     * folded back): one pass over atoms instead of six products per pair */
    pair_virial_fdotr(p, out->virial);
    out->energy += embed;
    (void)e;
    return 0;
}

/* Scratch of the one-element density pass: per thread, room for the
 * longest list (squared distances, inner distances, outer indices). */
static int eam_reserve_lists(struct eam *m, const struct nlist *nl, int nt, struct err *e)
{
    int maxnb = 1;
    for (int i = 0; i < nl->n; i++)
        if (nl->offset[i + 1] - nl->offset[i] > maxnb)
            maxnb = nl->offset[i + 1] - nl->offset[i];
    m->maxnb = maxnb;
    size_t need = (size_t)nt * maxnb;
    if (need <= m->cap_pairbuf)
        return 0;
    size_t cap = need + need / 4;
    double *pb = realloc(m->pairbuf, 2 * cap * sizeof *pb);
    if (pb)
        m->pairbuf = pb;
    int *jb = realloc(m->jbuf, cap * sizeof *jb);
    if (jb)
        m->jbuf = jb;
    if (!pb || !jb)
        return err_nomem(e, "EAM pair scratch");
    m->cap_pairbuf = cap;
    return 0;
}

static int eam_compute(struct potential *pot, struct particles *p, const struct nlist *nl,
                       int flags, struct force_result *out, struct err *e)
{
    struct eam *m = (struct eam *)pot;
    int nt = pot->nthreads < 1 ? 1 : pot->nthreads;
    int ntot = p->n_owned + p->n_ghost;
    int rc = eam_reserve(m, ntot, e);
    if (!rc)
        rc = thread_accum_reserve(&m->rho_acc, nt, (size_t)ntot, e);
    if (!rc)
        rc = pair_scratch_begin(&m->scratch, p, flags, nt, e);
    if (rc)
        return rc;
    if (m->tab1) {
        if ((rc = eam_reserve_lists(m, nl, nt, e)))
            return rc;
        return eam_compute_one(m, p, nl, flags, out, e);
    }
    const int *tmap = pot->type_map;
    const double cutsq = m->cutsq;
    memset(m->rho, 0, (size_t)ntot * sizeof(double));

    /* pass 1: densities */
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        double *rho = thread_accum_target(&m->rho_acc, tid, m->rho, (size_t)ntot);
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
            const int ti = tmap[p->type[i]];
            double rhoi = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= cutsq)
                    continue;
                int tj = tmap[p->type[j]];
                double q;
                int im = eam_spline_locate(m->rhor[tj][ti], sqrt(r2), &q);
                rhoi += eam_spline_value(m->rhor[tj][ti], im, q);
                rho[j] += eam_spline_value(m->rhor[ti][tj], im, q);
            }
            rho[i] += rhoi;
        }
    }
    thread_accum_reduce(&m->rho_acc, m->rho, (size_t)ntot);
    ghost_reverse_add(p, m->rho, 1);

    double embed = eam_embed(m, p, nl, flags);
    ghost_forward(p, m->fp, 1);

    /* pass 2: forces */
    const double *fp = m->fp;
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        struct pair_target t = pair_scratch_target(&m->scratch, p, tid);
        double esum = 0, w[6] = {0};
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
            const int ti = tmap[p->type[i]];
            const double fpi = fp[i];
            double fxi = 0, fyi = 0, fzi = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= cutsq)
                    continue;
                int tj = tmap[p->type[j]];
                double r = sqrt(r2), q;
                int im = eam_spline_locate(m->z2r[ti][tj], r, &q);
                /* rho'_i: derivative of the density i gives j; rho'_j: that j gives i */
                double rhoip = eam_spline_deriv(m->rhor[ti][tj], im, q);
                double rhojp = eam_spline_deriv(m->rhor[tj][ti], im, q);
                double z2p = eam_spline_deriv(m->z2r[ti][tj], im, q);
                double z2 = eam_spline_value(m->z2r[ti][tj], im, q);
                double recip = 1.0 / r;
                double phi = z2 * recip;
                double phip = z2p * recip - phi * recip;
                double psip = fpi * rhojp + fp[j] * rhoip + phip;
                double fpair = -psip * recip;
                fxi += dx * fpair;
                fyi += dy * fpair;
                fzi += dz * fpair;
                t.f[3 * j] -= dx * fpair;
                t.f[3 * j + 1] -= dy * fpair;
                t.f[3 * j + 2] -= dz * fpair;
                esum += phi;
                pair_tally_virial(w, dx, dy, dz, fpair);
                if (t.pe)
                    pair_tally_peratom(&t, i, j, phi, dx, dy, dz, fpair);
            }
            t.f[3 * i] += fxi;
            t.f[3 * i + 1] += fyi;
            t.f[3 * i + 2] += fzi;
        }
        pair_scratch_store_sums(&m->scratch, tid, esum, w);
    }
    /* the per-atom embedding energies written above live in thread 0's
     * (shared) target, so they survive the reduction */
    pair_scratch_end(&m->scratch, p, out);
    out->energy += embed;
    return 0;
}

static void eam_destroy(struct potential *pot)
{
    struct eam *m = (struct eam *)pot;
    for (int a = 0; a < NE; a++)
        eam_spline_free(&m->frho[a]);
    for (int k = 0; k < NE * NE; k++) {
        eam_spline_free(&m->rhor_store[k]);
        eam_spline_free(&m->z2r_store[k]);
    }
    thread_accum_free(&m->rho_acc);
    pair_scratch_free(&m->scratch);
    free(m->tab1);
    free(m->pairbuf);
    free(m->jbuf);
    free(m->ninner);
    free(m->rho);
    free(m->fp);
    free(m);
}

static const struct potential_ops eam_ops = {"eam", eam_compute, eam_destroy};
static const struct potential_ops eam_alloy_ops = {"eam/alloy", eam_compute, eam_destroy};
static const struct potential_ops eam_fs_ops = {"eam/fs", eam_compute, eam_destroy};

static int eam_create_format(struct cfg_obj *o, struct potential **out, enum eam_format fmt)
{
    char path[512];
    char keypath[CFG_PATH_MAX];
    snprintf(keypath, sizeof keypath, "%s.file", o->path);
    int rc = potential_file_key(o, path, sizeof path);
    const char *names[NE];
    int nnames = 0;
    if (!rc)
        rc = cfg_strings(o, "elements", 0, names, NE, &nnames);
    if (rc || o->cfg->shallow)
        return rc;
    struct eam_data d;
    if ((rc = eam_data_read(path, fmt, &d, o->cfg->err))) {
        char msg[ERR_MSG_MAX];
        snprintf(msg, sizeof msg, "%s", o->cfg->err->msg);
        return cfg_error_at(o->cfg, keypath, "corrupt or unreadable EAM file: %s", msg);
    }
    struct eam *m = calloc(1, sizeof *m);
    if (!m) {
        eam_data_free(&d);
        return err_nomem(o->cfg->err, "eam");
    }
    m->base.ops = fmt == EAM_FUNCFL ? &eam_ops : fmt == EAM_SETFL ? &eam_alloy_ops : &eam_fs_ops;
    m->base.list_kind = NLIST_HALF;
    m->base.cutoff = d.cut;
    m->cutsq = d.cut * d.cut;
    m->rhomax = d.rhomax;
    int ne = d.ne;
    m->ne = ne;

    /* elements: all of the file's by default, in file order (the default is
     * a function of the file, so it is not written into the case) */
    if (nnames == 0) {
        nnames = ne;
        for (int a = 0; a < ne; a++)
            names[a] = d.element[a];
    }
    int sel[NE];
    for (int k = 0; !rc && k < nnames; k++) {
        sel[k] = -1;
        for (int a = 0; a < ne; a++)
            if (strcmp(d.element[a], names[k]) == 0)
                sel[k] = a;
        for (int l = 0; l < k && sel[k] >= 0; l++)
            if (strcmp(names[l], names[k]) == 0) {
                char ep[CFG_PATH_MAX];
                snprintf(ep, sizeof ep, "%s.elements[%d]", o->path, k);
                rc = cfg_error_at(o->cfg, ep, "element '%s' is listed twice", names[k]);
            }
        if (!rc && sel[k] < 0) {
            char ep[CFG_PATH_MAX];
            snprintf(ep, sizeof ep, "%s.elements[%d]", o->path, k);
            rc = cfg_error_at(o->cfg, ep, "element '%s' is not in %s", names[k], path);
        }
    }
    /* splines of the whole file; the selection only maps names */
    for (int a = 0; !rc && a < ne; a++) {
        if (eam_spline_build(&m->frho[a], d.frho[a], d.nrho, d.drho))
            rc = err_nomem(o->cfg->err, "EAM spline");
        for (int b = 0; !rc && b < ne; b++) {
            int k = a * ne + b;
            if (d.rhor[k] && eam_spline_build(&m->rhor_store[k], d.rhor[k], d.nr, d.dr))
                rc = err_nomem(o->cfg->err, "EAM spline");
            if (!rc && d.z2r[k] && eam_spline_build(&m->z2r_store[k], d.z2r[k], d.nr, d.dr))
                rc = err_nomem(o->cfg->err, "EAM spline");
        }
    }
    if (rc) {
        eam_data_free(&d);
        eam_destroy(&m->base);
        return rc;
    }
    /* element-index tables over the selected elements */
    m->base.nelements = nnames;
    for (int k = 0; k < nnames; k++) {
        snprintf(m->base.element[k], sizeof m->base.element[k], "%s", names[k]);
        m->base.mass[k] = d.mass[sel[k]];
        m->sel[k] = sel[k];
    }
    for (int k = 0; k < nnames; k++)
        for (int l = 0; l < nnames; l++) {
            int a = sel[k], b = sel[l];
            m->rhor[k][l] = fmt == EAM_FS ? &m->rhor_store[a * ne + b] : &m->rhor_store[a * ne];
            m->z2r[k][l] = a >= b ? &m->z2r_store[a * ne + b] : &m->z2r_store[b * ne + a];
        }
    if (nnames == 1) {
        const struct eam_spline *rs = m->rhor[0][0], *zs = m->z2r[0][0];
        m->nr1 = rs->n;
        m->rdr1 = rs->rdelta;
        m->tab1 = aligned_alloc(64, (size_t)64 * rs->n);
        if (!m->tab1) {
            eam_data_free(&d);
            eam_destroy(&m->base);
            return err_nomem(o->cfg->err, "EAM table");
        }
        for (int k = 0; k < rs->n; k++)
            for (int c = 0; c < 4; c++) {
                m->tab1[8 * k + c] = rs->c[7 * k + 3 + c];
                m->tab1[8 * k + 4 + c] = zs->c[7 * k + 3 + c];
            }
    }
    snprintf(m->base.description, sizeof m->base.description, "EAM (%s) from %s, cutoff %g Å",
             m->base.ops->style, path, d.cut);
    snprintf(m->base.source_path, sizeof m->base.source_path, "%s", path);
    snprintf(m->base.cutoff_source, sizeof m->base.cutoff_source, "%s:%d", path, d.cut_line);
    eam_data_free(&d);
    *out = &m->base;
    return 0;
}

int eam_funcfl_create(struct cfg_obj *o, struct potential **out)
{
    return eam_create_format(o, out, EAM_FUNCFL);
}
int eam_setfl_create(struct cfg_obj *o, struct potential **out)
{
    return eam_create_format(o, out, EAM_SETFL);
}
int eam_fs_create(struct cfg_obj *o, struct potential **out)
{
    return eam_create_format(o, out, EAM_FS);
}
