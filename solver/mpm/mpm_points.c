/* mpm_points: allocation, append and reorder of the material point arrays. */
#include "mpm/mpm_points.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int mpm_points_init(struct mpm_points *p, int nstate, struct err *e)
{
    memset(p, 0, sizeof *p);
    if (nstate < 0)
        return err_set(e, ERR_RUNTIME, "mpm_points_init: negative state count");
    p->nstate = nstate;
    return 0;
}

void mpm_points_free(struct mpm_points *p)
{
    free(p->x);
    free(p->x0);
    free(p->v);
    free(p->mass);
    free(p->vol0);
    free(p->vol);
    free(p->stress);
    free(p->F);
    free(p->eint);
    free(p->state);
    free(p->fext);
    free(p->body);
    free(p->id);
    free(p->mask);
    memset(p, 0, sizeof *p);
}

static int grow(void **ptr, long cap, size_t per, struct err *e)
{
    if (per == 0)
        return 0;
    void *q = realloc(*ptr, (size_t)cap * per);
    if (!q)
        return err_nomem(e, "material points");
    *ptr = q;
    return 0;
}

int mpm_points_reserve(struct mpm_points *p, long n, struct err *e)
{
    if (n <= p->cap)
        return 0;
    long cap = n;   /* exact: the builder counts first; mpm_points_add doubles */
    int rc = 0;
    rc = rc ? rc : grow((void **)&p->x, cap, 3 * sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->x0, cap, 3 * sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->v, cap, 3 * sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->mass, cap, sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->vol0, cap, sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->vol, cap, sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->stress, cap, 6 * sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->F, cap, 9 * sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->eint, cap, sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->state, cap, (size_t)p->nstate * sizeof(double), e);
    if (p->fext)
        rc = rc ? rc : grow((void **)&p->fext, cap, 3 * sizeof(double), e);
    rc = rc ? rc : grow((void **)&p->body, cap, sizeof(int32_t), e);
    rc = rc ? rc : grow((void **)&p->id, cap, sizeof(int64_t), e);
    rc = rc ? rc : grow((void **)&p->mask, cap, sizeof(uint32_t), e);
    if (!rc)
        p->cap = cap;
    return rc;
}

long mpm_points_add(struct mpm_points *p, const double x[3], const double v[3], double mass,
                    double vol, int body, int64_t id, struct err *e)
{
    if (p->n >= p->cap && mpm_points_reserve(p, p->cap ? 2 * p->cap : 1024, e) != 0)
        return -1;
    long i = p->n++;
    for (int d = 0; d < 3; d++) {
        p->x[3 * i + d] = x[d];
        p->x0[3 * i + d] = x[d];
        p->v[3 * i + d] = v[d];
        if (p->fext)
            p->fext[3 * i + d] = 0.0;
    }
    p->mass[i] = mass;
    p->vol0[i] = vol;
    p->vol[i] = vol;
    memset(p->stress + 6 * i, 0, 6 * sizeof(double));
    double *F = p->F + 9 * i;
    memset(F, 0, 9 * sizeof(double));
    F[0] = F[4] = F[8] = 1.0;
    p->eint[i] = 0.0;
    for (int k = 0; k < p->nstate; k++)
        p->state[(long)p->nstate * i + k] = 0.0;
    p->body[i] = body;
    p->id[i] = id;
    p->mask[i] = 0;
    return i;
}

int mpm_points_enable_fext(struct mpm_points *p, struct err *e)
{
    if (p->fext)
        return 0;
    p->fext = calloc((size_t)(p->cap > 0 ? p->cap : 1), 3 * sizeof(double));
    if (!p->fext)
        return err_nomem(e, "material point external forces");
    return 0;
}

/* a[k*nc + c] <- a[perm[k]*nc + c], one component at a time through tmp
 * (threads share each component's loops; called from outside a parallel
 * region) */
static void permute_doubles(double *a, int nc, long n, const int32_t *perm, double *tmp, int nt)
{
    if (!a)
        return;
    for (int c = 0; c < nc; c++) {
#pragma omp parallel for schedule(static) num_threads(nt)
        for (long k = 0; k < n; k++)
            tmp[k] = a[(long)perm[k] * nc + c];
#pragma omp parallel for schedule(static) num_threads(nt)
        for (long k = 0; k < n; k++)
            a[k * nc + c] = tmp[k];
    }
}

/* The cycles of perm, for a reorder that moves few points: list[] holds
 * each cycle as -(k0 + 1), perm[k0], perm[perm[k0]], ... (up to, not
 * including, k0 again); fixed points are not listed.  Returns the length. */
static long perm_cycles(const int32_t *perm, long n, int32_t *list, uint8_t *seen)
{
    memset(seen, 0, (size_t)(n + 7) / 8);
    long len = 0;
    for (long k0 = 0; k0 < n; k0++) {
        if (perm[k0] == k0 || (seen[k0 >> 3] >> (k0 & 7) & 1))
            continue;
        list[len++] = (int32_t)(-(k0 + 1));
        seen[k0 >> 3] |= (uint8_t)(1u << (k0 & 7));
        for (long k = perm[k0]; k != k0; k = perm[k]) {
            list[len++] = (int32_t)k;
            seen[k >> 3] |= (uint8_t)(1u << (k & 7));
        }
    }
    return len;
}

/* a[k] <- a[perm[k]] for records of `rec` bytes, following the cycles:
 * every moved record is read and written once, the others not touched. */
static void permute_cycles(void *a, size_t rec, const int32_t *list, long len)
{
    if (!a || rec == 0 || len == 0)
        return;
    char *b = a, saved[16 * sizeof(double)];
    long dst = -1;
    for (long i = 0; i < len; i++) {
        long k = list[i];
        if (k < 0) {   /* a new cycle: close the last one */
            if (dst >= 0)
                memcpy(b + (size_t)dst * rec, saved, rec);
            dst = -k - 1;
            memcpy(saved, b + (size_t)dst * rec, rec);
        } else {
            memcpy(b + (size_t)dst * rec, b + (size_t)k * rec, rec);
            dst = k;
        }
    }
    memcpy(b + (size_t)dst * rec, saved, rec);
}

void mpm_points_permute(struct mpm_points *p, const int32_t *perm, double *tmp, int nthreads)
{
    long n = p->n;
    if (n < 2)
        return;   /* nothing to move (and a rank of bricks may hold no point: no scratch) */
    long moved = 0;
    for (long k = 0; k < n; k++)
        moved += perm[k] != k;
    if (moved <= n / 4 && p->nstate <= 16) {
        /* few points move (a periodic reorder): follow the cycles, whole
         * records at a time, through the scratch as the cycle list (4n
         * bytes) and a bitmap (n / 8 bytes) */
        int32_t *list = (int32_t *)tmp;
        long len = perm_cycles(perm, n, list, (uint8_t *)(list + n));
        /* the arrays are independent: threads take them one by one, the
         * largest records first */
        void *const arr[14] = {p->F,    p->stress, p->x,    p->x0,   p->v,  p->fext, p->state,
                               p->mass, p->vol0,   p->vol,  p->eint, p->id, p->body, p->mask};
        const size_t rec[14] = {9 * sizeof(double), 6 * sizeof(double), 3 * sizeof(double),
                                3 * sizeof(double), 3 * sizeof(double), 3 * sizeof(double),
                                (size_t)p->nstate * sizeof(double),     sizeof(double),
                                sizeof(double),     sizeof(double),     sizeof(double),
                                sizeof *p->id,      sizeof *p->body,    sizeof *p->mask};
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
        for (int a = 0; a < 14; a++)
            permute_cycles(arr[a], rec[a], list, len);
        return;
    }
    permute_doubles(p->x, 3, n, perm, tmp, nthreads);
    permute_doubles(p->x0, 3, n, perm, tmp, nthreads);
    permute_doubles(p->v, 3, n, perm, tmp, nthreads);
    permute_doubles(p->mass, 1, n, perm, tmp, nthreads);
    permute_doubles(p->vol0, 1, n, perm, tmp, nthreads);
    permute_doubles(p->vol, 1, n, perm, tmp, nthreads);
    permute_doubles(p->stress, 6, n, perm, tmp, nthreads);
    permute_doubles(p->F, 9, n, perm, tmp, nthreads);
    permute_doubles(p->eint, 1, n, perm, tmp, nthreads);
    permute_doubles(p->state, p->nstate, n, perm, tmp, nthreads);
    permute_doubles(p->fext, 3, n, perm, tmp, nthreads);
    /* integer arrays: through the same scratch, as raw 8-byte words */
    int64_t *t64 = (int64_t *)tmp;
    for (long k = 0; k < n; k++)
        t64[k] = p->id[perm[k]];
    memcpy(p->id, t64, (size_t)n * sizeof *p->id);
    int32_t *t32 = (int32_t *)tmp;
    for (long k = 0; k < n; k++)
        t32[k] = p->body[perm[k]];
    memcpy(p->body, t32, (size_t)n * sizeof *p->body);
    uint32_t *u32 = (uint32_t *)tmp;
    for (long k = 0; k < n; k++)
        u32[k] = p->mask[perm[k]];
    memcpy(p->mask, u32, (size_t)n * sizeof *p->mask);
}

double mpm_points_bytes_per_point(const struct mpm_points *p)
{
    double b = (3 + 3 + 3 + 1 + 1 + 1 + 6 + 9 + 1) * sizeof(double) +
               (double)p->nstate * sizeof(double) + sizeof(int32_t) + sizeof(int64_t) +
               sizeof(uint32_t);
    if (p->fext)
        b += 3 * sizeof(double);
    return b;
}

/* Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations:
 * A (row-major) becomes diagonal, V holds the eigenvectors in its columns. */
static void jacobi3(double A[9], double V[9])
{
    for (int k = 0; k < 9; k++)
        V[k] = (k % 4 == 0);
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
        double diag = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
        if (off <= 1e-30 * diag || off == 0)
            return;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                double apq = A[3 * p + q];
                if (apq == 0)
                    continue;
                double theta = (A[3 * q + q] - A[3 * p + p]) / (2 * apq);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; k++) {   /* A <- J^T A J */
                    double akp = A[3 * k + p], akq = A[3 * k + q];
                    A[3 * k + p] = c * akp - s * akq;
                    A[3 * k + q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = A[3 * p + k], aqk = A[3 * q + k];
                    A[3 * p + k] = c * apk - s * aqk;
                    A[3 * q + k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = V[3 * k + p], vkq = V[3 * k + q];
                    V[3 * k + p] = c * vkp - s * vkq;
                    V[3 * k + q] = s * vkp + c * vkq;
                }
            }
    }
}

void mpm_points_strain(const struct mpm_points *p, long i, double eps[6])
{
    const double *F = p->F + 9 * i;
    double B[9], V[9];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            B[3 * a + b] = F[3 * a] * F[3 * b] + F[3 * a + 1] * F[3 * b + 1] +
                           F[3 * a + 2] * F[3 * b + 2];
    jacobi3(B, V);
    double l[3];
    for (int k = 0; k < 3; k++)
        l[k] = 0.5 * log(B[4 * k] > 0 ? B[4 * k] : 1e-300);
    static const int ia[6] = {0, 1, 2, 0, 0, 1}, ib[6] = {0, 1, 2, 1, 2, 2};
    for (int c = 0; c < 6; c++) {
        double sum = 0;
        for (int k = 0; k < 3; k++)
            sum += l[k] * V[3 * ia[c] + k] * V[3 * ib[c] + k];
        eps[c] = sum;
    }
}
