/*
 * block_average: mean and standard error of a correlated time series by
 * block averaging (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989)):
 * the series is cut into `nblocks` equal blocks and the error is the
 * standard deviation of the block means over sqrt(nblocks - 1).  Blocks
 * longer than the correlation time make the estimate honest.
 */
#ifndef CASCADE_BLOCK_AVERAGE_H
#define CASCADE_BLOCK_AVERAGE_H

/* Mean of x[0..n); *sem (may be NULL) gets the block standard error (NAN
 * when n < nblocks or nblocks < 2). */
double block_average(const double *x, long n, int nblocks, double *sem);

#endif
