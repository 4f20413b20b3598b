/*
 * parallel: the one file of cascade-solver that talks MPI.
 *
 * A solver started by mpirun (Open MPI sets OMPI_COMM_WORLD_SIZE, PMIx sets
 * PMIX_RANK) initialises MPI; started any other way it does not, so a plain
 * run never pays for MPI.  With N > 1 ranks the MD engine runs either on
 * bricks (core/halo.h: each rank owns a brick of the box; this file gives
 * it the Cartesian grid, point-to-point exchanges, gathers and global
 * sums) or replicated data: every rank holds every particle, computes the
 * forces of its slice of owned particles (neighbour lists are built for
 * the slice only), and the partial forces, densities, energies and virials
 * are summed over ranks.  Sums go to rank 0 and are broadcast back, so
 * every rank holds bitwise the same numbers.  Rank 0 alone writes output
 * files.
 */
#ifndef CASCADE_PARALLEL_H
#define CASCADE_PARALLEL_H

#include <stddef.h>

#include "util/err.h"

struct parallel {
    int rank, size;
    int mpi;          /* MPI initialised by us */
};

/* Serial defaults (rank 0 of 1) unless launched by mpirun. */
int parallel_init(struct parallel *par, int *argc, char ***argv, struct err *e);
void parallel_finalize(struct parallel *par);

/* buf[k] <- sum over ranks of buf[k]; identical on every rank.  No-op in
 * serial runs (par NULL or size 1). */
void parallel_sum(const struct parallel *par, double *buf, size_t n);

/* This rank's slice [lo, hi) of n items. */
void parallel_range(const struct parallel *par, int n, int *lo, int *hi);

/* 1 on every rank when flag is non-zero on any rank. */
int parallel_any(const struct parallel *par, int flag);

/* The one error of a run under MPI, agreed by every rank (collective):
 * the lowest rank whose error is its own (not err_set_elsewhere), else
 * the lowest that failed.  Every rank returns that error's class and holds
 * its message in *e, prefixed "rank N: " when N is not 0, so rank 0 can
 * print and record it and every rank exits with the same code whichever
 * rank mpirun hears from first.  0 on every rank when none failed. */
int parallel_agree_error(const struct parallel *par, int rc, struct err *e);

/* --- point-to-point and collectives of the brick decomposition (halo.h) --- */

/* The Cartesian grid of ranks (MPI_Cart_create without reordering, so a
 * grid rank is the world rank): this rank's coordinates and its neighbours
 * below and above along each axis (-1 at a non-periodic edge). */
int parallel_cart(const struct parallel *par, const int dims[3], const int periodic[3],
                  int coords[3], int nbr[3][2], struct err *e);

/* Send sbytes to rank dest while receiving from rank src (either -1: none)
 * into *rbuf, grown with realloc (*rcap its capacity); *rbytes the bytes
 * received.  dest == src == this rank copies locally. */
int parallel_sendrecv(const struct parallel *par, int dest, const void *sbuf, size_t sbytes,
                      int src, void **rbuf, size_t *rcap, size_t *rbytes, struct err *e);

/* The same when both sides know the sizes (a recorded halo swap): one
 * message, rbuf holds rbytes. */
int parallel_sendrecv_known(const struct parallel *par, int dest, const void *sbuf, size_t sbytes,
                            int src, void *rbuf, size_t rbytes, struct err *e);

/* buf[k] <- max (min) over ranks of buf[k], on every rank. */
void parallel_max(const struct parallel *par, double *buf, size_t n);
void parallel_min(const struct parallel *par, double *buf, size_t n);

/* sum[k] <- sum over ranks of sum[k] (added in rank order: the same bits
 * on every rank; two ranks give what parallel_sum gives) and mx[k] <- max
 * over ranks of mx[k], in one collective instead of two: a per-step
 * reduction of energies beside a largest speed or a flag costs one sync
 * point.  Falls back to parallel_sum and parallel_max when the gather
 * buffer cannot be had. */
void parallel_sum_max(const struct parallel *par, double *sum, size_t ns, double *mx, size_t nm);

/* out[r] = v of rank r (out holds size entries), on every rank. */
void parallel_allgather_long(const struct parallel *par, long v, long *out);

/* The blocks of every rank concatenated in rank order on rank 0 (*rbuf
 * malloc'ed there, NULL elsewhere). */
int parallel_gather_bytes(const struct parallel *par, const void *sbuf, size_t sbytes,
                          void **rbuf, size_t *rbytes, struct err *e);

/* The n bytes of rank 0's buf into buf on every rank. */
int parallel_bcast_bytes(const struct parallel *par, void *buf, size_t n, struct err *e);

/* Rank 0's result of a step only it did (a file it read) made every
 * rank's: rank 0's rc is returned on every rank, and when it failed its
 * class and message are copied into every rank's e, so each rank stops
 * with rank 0's words (file:line and field) and exit code.  Collective;
 * returns rc unchanged in a serial run. */
int parallel_bcast_err(const struct parallel *par, int rc, struct err *e);

/* The reverse of parallel_gather_bytes: rank 0's sbuf holds the blocks of
 * every rank concatenated in rank order, rank r's block bytes[r] long
 * (bytes given on every rank); each rank receives its own into rbuf. */
int parallel_scatter_bytes(const struct parallel *par, const void *sbuf, const long *bytes,
                           void *rbuf, struct err *e);

/* recv[r] = what rank r put in its send[me] (one int per pair of ranks). */
int parallel_alltoall_int(const struct parallel *par, const int *send, int *recv, struct err *e);

/* Blocks of bytes to every rank at once: scount[r] bytes from sbuf +
 * sdispl[r] go to rank r, which receives them at its rbuf + rdispl[me]
 * (rcount, rdispl: what each rank sends here, from parallel_alltoall_int).
 * Serial: the rank's own block is copied. */
int parallel_alltoallv_bytes(const struct parallel *par, const void *sbuf, const int *scount,
                             const int *sdispl, void *rbuf, const int *rcount, const int *rdispl,
                             struct err *e);

#endif
