/*
 * sc_density: pass 1 of the Sutton-Chen force (core/sc_form.h), shared by
 * the atomistic potential (md/sutton_chen.c) and the coarse-grained DPD
 * conservative force (dpd/dpd_conservative.c):
 *   rho_i = sum_j rho(r_ij) over a half list (both ends of each pair, ghost
 *   parts added to their owners), F(rho_i) and F'(rho_i) for every owned
 *   particle, F' sent out to the ghosts for pass 2.
 * Threads accumulate into private buffers summed in thread order
 * (core/thread_accum.h), so a thread count always gives the same sums.
 */
#ifndef CASCADE_SC_DENSITY_H
#define CASCADE_SC_DENSITY_H

#include "core/neighbor.h"
#include "core/particles.h"
#include "core/sc_form.h"
#include "core/thread_accum.h"

/* rho and fp hold n_owned + n_ghost entries, acc is reserved for nthreads
 * buffers of that length.  Returns the embedding energy of the particles
 * in this MPI rank's slice [nl->ilo, nl->ihi) (eV) and, when pe is not
 * NULL, writes it per particle there (other entries untouched). */
double sc_density_embed(const struct sc_params *sc, struct particles *p, const struct nlist *nl,
                        struct thread_accum *acc, int nthreads, double *rho, double *fp,
                        double *pe);

/* The second half of sc_density_embed, for a caller with its own pair
 * loop (dpd/dpd_conservative.c): the threads' partial densities in acc
 * (targets of thread_accum_target over rho, zeroed before the loop) summed,
 * ghost parts added to their owners, then F, F' and the energy as above. */
double sc_density_finish(const struct sc_params *sc, struct particles *p, const struct nlist *nl,
                         struct thread_accum *acc, double *rho, double *fp, double *pe);

#endif
