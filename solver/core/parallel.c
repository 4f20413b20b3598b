/* parallel: MPI start-up and the reductions of replicated-data runs. */
#include "core/parallel.h"

#include <limits.h>
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_SIZE");
}

int parallel_init(struct parallel *par, int *argc, char ***argv, struct err *e)
{
    memset(par, 0, sizeof *par);
    par->size = 1;
    if (!launched_by_mpirun())
        return 0;
    if (MPI_Init(argc, argv) != MPI_SUCCESS)
        return err_set(e, ERR_RUNTIME, "MPI_Init failed");
    par->mpi = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &par->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &par->size);
    return 0;
}

void parallel_finalize(struct parallel *par)
{
    if (par->mpi)
        MPI_Finalize();
    par->mpi = 0;
}

void parallel_sum(const struct parallel *par, double *buf, size_t n)
{
    if (!par || par->size <= 1 || n == 0)
        return;
    /* two ranks: one allreduce.  Each element is a0 + a1 on both ranks
     * (IEEE addition of two operands is commutative, whatever order an
     * allreduce algorithm adds them in), the bits a reduce gives; one
     * collective instead of two per sum, a sync point less each time (the
     * bricks' energy and kinetic sums every step). */
    if (par->size == 2 && n <= ((size_t)1 << 26)) {
        MPI_Allreduce(MPI_IN_PLACE, buf, (int)n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
        return;
    }
    /* reduce + broadcast rather than allreduce: all ranks get the same bits
     * (more than two operands may be associated differently on each rank) */
    const size_t chunk = (size_t)1 << 26;
    for (size_t at = 0; at < n; at += chunk) {
        int len = (int)(n - at < chunk ? n - at : chunk);
        if (par->rank == 0)
            MPI_Reduce(MPI_IN_PLACE, buf + at, len, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        else
            MPI_Reduce(buf + at, NULL, len, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        MPI_Bcast(buf + at, len, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }
}

void parallel_range(const struct parallel *par, int n, int *lo, int *hi)
{
    if (!par || par->size <= 1) {
        *lo = 0;
        *hi = n;
        return;
    }
    *lo = (int)((long)n * par->rank / par->size);
    *hi = (int)((long)n * (par->rank + 1) / par->size);
}

int parallel_any(const struct parallel *par, int flag)
{
    if (!par || par->size <= 1)
        return flag != 0;
    int in = flag != 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return out;
}

int parallel_agree_error(const struct parallel *par, int rc, struct err *e)
{
    if (!par || par->size <= 1)
        return rc;
    /* the chosen rank by one MIN: own errors first, then the others */
    int size = par->size;
    int key = !rc ? 2 * size : (e && e->elsewhere) ? size + par->rank : par->rank;
    int first = 2 * size;
    MPI_Allreduce(&key, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == 2 * size)
        return 0;
    int root = first % size;
    struct {
        int code;
        char msg[ERR_MSG_MAX];
    } m;
    m.code = rc;
    if (par->rank == root)
        snprintf(m.msg, sizeof m.msg, "%s", e ? e->msg : "");
    MPI_Bcast(&m, (int)sizeof m, MPI_BYTE, root, MPI_COMM_WORLD);
    if (root == 0)
        err_set(e, m.code, "%s", m.msg);
    else
        err_set(e, m.code, "rank %d: %s", root, m.msg);
    if (e)
        e->elsewhere = first >= size;
    return m.code;
}

int parallel_cart(const struct parallel *par, const int dims[3], const int periodic[3],
                  int coords[3], int nbr[3][2], struct err *e)
{
    if (!par || !par->mpi) {   /* one rank without MPI: its own neighbour when periodic */
        for (int d = 0; d < 3; d++) {
            coords[d] = 0;
            nbr[d][0] = nbr[d][1] = periodic[d] ? 0 : -1;
        }
        return 0;
    }
    MPI_Comm cart;
    int rc = MPI_Cart_create(MPI_COMM_WORLD, 3, (int *)dims, (int *)periodic, 0, &cart);
    if (rc != MPI_SUCCESS || cart == MPI_COMM_NULL)
        return err_set(e, ERR_RUNTIME, "MPI_Cart_create %d x %d x %d failed", dims[0], dims[1],
                       dims[2]);
    int me;
    MPI_Comm_rank(cart, &me);
    MPI_Cart_coords(cart, me, 3, coords);
    for (int d = 0; d < 3; d++) {
        MPI_Cart_shift(cart, d, 1, &nbr[d][0], &nbr[d][1]);
        for (int k = 0; k < 2; k++)
            if (nbr[d][k] == MPI_PROC_NULL)
                nbr[d][k] = -1;
    }
    MPI_Comm_free(&cart);
    return 0;
}

static int grow_bytes(void **buf, size_t *cap, size_t n, struct err *e)
{
    if (n <= *cap && *buf)
        return 0;
    size_t c = n + n / 4 + 256;
    void *b = realloc(*buf, c);
    if (!b)
        return err_nomem(e, "halo buffer");
    *buf = b;
    *cap = c;
    return 0;
}

int parallel_sendrecv(const struct parallel *par, int dest, const void *sbuf, size_t sbytes,
                      int src, void **rbuf, size_t *rcap, size_t *rbytes, struct err *e)
{
    int me = par ? par->rank : 0;
    *rbytes = 0;
    if (dest < 0 && src < 0)
        return 0;
    if (dest == me && src == me) {
        if (grow_bytes(rbuf, rcap, sbytes, e))
            return ERR_RUNTIME;
        if (sbytes)
            memcpy(*rbuf, sbuf, sbytes);
        *rbytes = sbytes;
        return 0;
    }
    if (!par || !par->mpi)
        return err_set(e, ERR_RUNTIME, "halo exchange with rank %d/%d without MPI", dest, src);
    long scount = dest >= 0 ? (long)sbytes : 0, rcount = 0;
    MPI_Sendrecv(&scount, 1, MPI_LONG, dest >= 0 ? dest : MPI_PROC_NULL, 1, &rcount, 1, MPI_LONG,
                 src >= 0 ? src : MPI_PROC_NULL, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (rcount < 0 || rcount > INT_MAX || scount > INT_MAX)
        return err_set(e, ERR_RUNTIME, "halo message of %ld bytes is beyond MPI's int count",
                       rcount > scount ? rcount : scount);
    if (grow_bytes(rbuf, rcap, (size_t)rcount, e))
        return ERR_RUNTIME;
    MPI_Sendrecv(sbuf, (int)scount, MPI_BYTE, dest >= 0 ? dest : MPI_PROC_NULL, 2, *rbuf,
                 (int)rcount, MPI_BYTE, src >= 0 ? src : MPI_PROC_NULL, 2, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
    *rbytes = (size_t)rcount;
    return 0;
}

int parallel_sendrecv_known(const struct parallel *par, int dest, const void *sbuf, size_t sbytes,
                            int src, void *rbuf, size_t rbytes, struct err *e)
{
    int me = par ? par->rank : 0;
    if (dest < 0 && src < 0)
        return 0;
    if (dest == me && src == me) {
        if (sbytes != rbytes)
            return err_set(e, ERR_RUNTIME, "halo swap with itself: %zu bytes sent, %zu expected",
                           sbytes, rbytes);
        if (sbytes)
            memcpy(rbuf, sbuf, sbytes);
        return 0;
    }
    if (!par || !par->mpi)
        return err_set(e, ERR_RUNTIME, "halo exchange with rank %d/%d without MPI", dest, src);
    if (sbytes > INT_MAX || rbytes > INT_MAX)
        return err_set(e, ERR_RUNTIME, "halo message beyond MPI's int count");
    MPI_Sendrecv(sbuf, dest >= 0 ? (int)sbytes : 0, MPI_BYTE, dest >= 0 ? dest : MPI_PROC_NULL, 3,
                 rbuf, src >= 0 ? (int)rbytes : 0, MPI_BYTE, src >= 0 ? src : MPI_PROC_NULL, 3,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return 0;
}

static void allreduce_op(const struct parallel *par, double *buf, size_t n, MPI_Op op)
{
    if (!par || par->size <= 1 || n == 0)
        return;
    MPI_Allreduce(MPI_IN_PLACE, buf, (int)n, MPI_DOUBLE, op, MPI_COMM_WORLD);
}

void parallel_max(const struct parallel *par, double *buf, size_t n)
{
    allreduce_op(par, buf, n, MPI_MAX);
}

void parallel_min(const struct parallel *par, double *buf, size_t n)
{
    allreduce_op(par, buf, n, MPI_MIN);
}

void parallel_sum_max(const struct parallel *par, double *sum, size_t ns, double *mx, size_t nm)
{
    if (!par || par->size <= 1 || ns + nm == 0)
        return;
    size_t n = ns + nm, p = (size_t)par->size;
    double *all = n <= (size_t)INT_MAX / p ? malloc(n * (p + 1) * sizeof *all) : NULL;
    if (!all) {
        parallel_sum(par, sum, ns);
        parallel_max(par, mx, nm);
        return;
    }
    double *mine = all + n * p;
    memcpy(mine, sum, ns * sizeof *sum);
    memcpy(mine + ns, mx, nm * sizeof *mx);
    MPI_Allgather(mine, (int)n, MPI_DOUBLE, all, (int)n, MPI_DOUBLE, MPI_COMM_WORLD);
    for (size_t k = 0; k < ns; k++) {
        double t = all[k];
        for (size_t r = 1; r < p; r++)
            t += all[r * n + k];
        sum[k] = t;
    }
    for (size_t k = 0; k < nm; k++) {
        double t = all[ns + k];
        for (size_t r = 1; r < p; r++) {
            double x = all[r * n + ns + k];
            t = isnan(t) || isnan(x) ? NAN : fmax(t, x);   /* a NaN (divergence) is kept */
        }
        mx[k] = t;
    }
    free(all);
}

void parallel_allgather_long(const struct parallel *par, long v, long *out)
{
    if (!par || par->size <= 1) {
        out[0] = v;
        return;
    }
    MPI_Allgather(&v, 1, MPI_LONG, out, 1, MPI_LONG, MPI_COMM_WORLD);
}

int parallel_gather_bytes(const struct parallel *par, const void *sbuf, size_t sbytes,
                          void **rbuf, size_t *rbytes, struct err *e)
{
    *rbuf = NULL;
    *rbytes = 0;
    int size = par ? par->size : 1, rank = par ? par->rank : 0;
    if (size <= 1) {
        *rbuf = malloc(sbytes ? sbytes : 1);
        if (!*rbuf)
            return err_nomem(e, "gather");
        memcpy(*rbuf, sbuf, sbytes);
        *rbytes = sbytes;
        return 0;
    }
    if (sbytes > INT_MAX)
        return err_set(e, ERR_RUNTIME, "gather of %zu bytes is beyond MPI's int count", sbytes);
    int mine = (int)sbytes;
    int *counts = rank == 0 ? malloc((size_t)size * sizeof *counts) : NULL;
    int *displs = rank == 0 ? malloc((size_t)size * sizeof *displs) : NULL;
    int bad = rank == 0 && (!counts || !displs);
    MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    long total = 0;
    if (rank == 0 && !bad) {
        for (int r = 0; r < size; r++) {
            displs[r] = (int)total;
            total += counts[r];
        }
        bad = total > INT_MAX || !(*rbuf = malloc(total ? (size_t)total : 1));
    }
    MPI_Bcast(&bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (bad) {
        free(counts);
        free(displs);
        free(*rbuf);
        *rbuf = NULL;
        return err_set(e, ERR_RUNTIME, "gather on rank 0: out of memory or beyond int counts");
    }
    MPI_Gatherv(sbuf, mine, MPI_BYTE, *rbuf, counts, displs, MPI_BYTE, 0, MPI_COMM_WORLD);
    *rbytes = (size_t)total;
    free(counts);
    free(displs);
    return 0;
}

int parallel_bcast_bytes(const struct parallel *par, void *buf, size_t n, struct err *e)
{
    if (!par || par->size <= 1 || n == 0)
        return 0;
    if (n > INT_MAX)
        return err_set(e, ERR_RUNTIME, "broadcast of %zu bytes is beyond MPI's int count", n);
    MPI_Bcast(buf, (int)n, MPI_BYTE, 0, MPI_COMM_WORLD);
    return 0;
}

int parallel_bcast_err(const struct parallel *par, int rc, struct err *e)
{
    if (!par || par->size <= 1)
        return rc;
    int code = rc;
    MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!code)
        return 0;
    /* the message goes with the code: the other ranks did not read the
     * file, so they have no words of their own */
    char msg[ERR_MSG_MAX];
    if (par->rank == 0)
        snprintf(msg, sizeof msg, "%s", e ? e->msg : "");
    MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, 0, MPI_COMM_WORLD);
    msg[sizeof msg - 1] = '\0';
    if (par->rank != 0)
        err_set(e, code, "%s", msg);
    return code;
}

int parallel_scatter_bytes(const struct parallel *par, const void *sbuf, const long *bytes,
                           void *rbuf, struct err *e)
{
    int size = par ? par->size : 1, rank = par ? par->rank : 0;
    if (size <= 1) {
        if (bytes[0] > 0)
            memcpy(rbuf, sbuf, (size_t)bytes[0]);
        return 0;
    }
    /* every rank checks the same counts: all refuse together */
    long total = 0;
    for (int r = 0; r < size; r++)
        total += bytes[r];
    if (total > INT_MAX)
        return err_set(e, ERR_RUNTIME, "scatter of %ld bytes is beyond MPI's int count", total);
    int *counts = malloc((size_t)size * sizeof *counts);
    int *displs = malloc((size_t)size * sizeof *displs);
    int bad = parallel_any(par, !counts || !displs);
    if (bad) {
        free(counts);
        free(displs);
        return err_nomem(e, "scatter counts");
    }
    long at = 0;
    for (int r = 0; r < size; r++) {
        counts[r] = (int)bytes[r];
        displs[r] = (int)at;
        at += bytes[r];
    }
    MPI_Scatterv(rank == 0 ? sbuf : NULL, counts, displs, MPI_BYTE, rbuf, counts[rank], MPI_BYTE,
                 0, MPI_COMM_WORLD);
    free(counts);
    free(displs);
    return 0;
}

int parallel_alltoall_int(const struct parallel *par, const int *send, int *recv, struct err *e)
{
    (void)e;
    if (!par || par->size <= 1 || !par->mpi) {
        recv[0] = send[0];
        return 0;
    }
    MPI_Alltoall(send, 1, MPI_INT, recv, 1, MPI_INT, MPI_COMM_WORLD);
    return 0;
}

int parallel_alltoallv_bytes(const struct parallel *par, const void *sbuf, const int *scount,
                             const int *sdispl, void *rbuf, const int *rcount, const int *rdispl,
                             struct err *e)
{
    (void)e;
    if (!par || par->size <= 1 || !par->mpi) {
        if (scount[0] > 0)
            memcpy((char *)rbuf + rdispl[0], (const char *)sbuf + sdispl[0], (size_t)scount[0]);
        return 0;
    }
    MPI_Alltoallv(sbuf, scount, sdispl, MPI_BYTE, rbuf, rcount, rdispl, MPI_BYTE,
                  MPI_COMM_WORLD);
    return 0;
}
