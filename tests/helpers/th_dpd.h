/*
 * th_dpd: helpers for the DPD tests -- a coarse-grained Sutton-Chen
 * parameter set and DPD models over small crystals.
 */
#ifndef CASCADE_TEST_HELPERS_DPD_H
#define CASCADE_TEST_HELPERS_DPD_H

#include "dpd/dpd.h"

/* Copper-like coarse-grained parameters (8 atoms per particle): eps 0.1 eV,
 * c 39.0, n 9, m 6, a 7.23 Å, cutoff 10.845 Å, mass 508.368 amu. */
void th_cg_params(struct cg_params *prm);

/* A DPD model over an fcc crystal of n^3 cells of edge a, periodic or with
 * free boundaries, positions displaced by up to `displace` Å; aborts the
 * test on failure. */
void th_dpd(struct dpd *d, long n, double a, int periodic, double displace,
            const struct dpd_settings *set, double dt, int nthreads, uint64_t seed);

/* Settings: isothermal DPD at T with friction gamma (amu/ps). */
struct dpd_settings th_dpd_settings(enum dpd_variant v, double gamma, double T);

#endif
