/*
 * handshake_profile: fields along one axis of a handshake model from both
 * sides in one series (Guo & Yang 2005, Figs. 4-8): slabs of fixed
 * reference position, each with the MD atoms (core and region I) whose
 * reference site lies in it and, separately, the material points (regions
 * II, III and the rest) whose initial position lies in it.
 *
 *   MD slab:   sigma = -sum_i (W_i + m_i v_i v_i) / V_slab, the virial
 *              stress of the slab (per-atom virial W_i, Schiotz et al.),
 *              with V_slab the slab's current volume: its atoms' atomic
 *              volumes stretched by the slab's mean displacement gradient
 *              along the axis (the cross-section is held by the periodic
 *              box), so that it is a Cauchy stress like the MPM one;
 *   MPM slab:  sigma = sum_p V_p sigma_p / sum_p V_p (current volumes).
 * Both give the mean displacement and velocity along the axis too.
 */
#ifndef CASCADE_HANDSHAKE_PROFILE_H
#define CASCADE_HANDSHAKE_PROFILE_H

#include "couple/handshake.h"

enum { HS_SRC_MD = 0, HS_SRC_MPM = 1 };

struct hs_slab {
    long n;             /* atoms or points */
    double stress[6];   /* eV/Å^3 */
    double u, v;        /* Å, Å/ps along the axis */
    double volume;      /* Å^3 */
    double mass;        /* amu (MPM slabs) */
};

#define HS_SLAB_SUMS 9    /* an MD slab's sums over the ranks: n, stress[6], u, v */
#define HS_SLAB_SUMS_MPM 11   /* an MPM slab's: n, stress[6], volume, u, v, mass */

struct hs_profile {
    int axis;
    double x0, width;   /* Å: slab k spans [x0 + k width, x0 + (k+1) width) */
    long nbins;
    struct hs_slab *md, *mpm;   /* nbins each */
    double *sums;       /* HS_SLAB_SUMS_MPM x nbins: the slabs' sums on bricks */
};

/* Slabs of `width` Å over the MPM domain along `axis`. */
int hs_profile_init(struct hs_profile *pr, const struct handshake *hs, int axis, double width,
                    struct err *e);
void hs_profile_free(struct hs_profile *pr);

/* Fill the slabs from the current state.  On MPI bricks (hs->md->halo)
 * the MD slabs are sums over every rank's atoms: collective, and every
 * rank gets the same profile. */
void hs_profile_compute(struct hs_profile *pr, const struct handshake *hs);

/* Reference position of slab k's centre (Å). */
static inline double hs_profile_x(const struct hs_profile *pr, long k)
{
    return pr->x0 + (k + 0.5) * pr->width;
}

/* Mean stress component c (eV/Å^3) of the slabs of one source whose
 * centres lie in [lo, hi); returns the number of slabs (0: *mean = NAN). */
long hs_profile_mean(const struct hs_profile *pr, int source, int c, double lo, double hi,
                     double *mean);

#endif
