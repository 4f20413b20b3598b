/*
 * dpd_bar: the geometry of a rectangular bar of (100) crystal planes -- the
 * flyer/target and tensile-rod samples of Chen et al. 2014 (Sec. 4.1) --
 * measured from its particles, so that an equilibrated (thermally rough,
 * slightly relaxed) sample read from a file gets the same faces as the
 * perfect lattice it came from.
 *
 * A face is the mean coordinate of the particles within half a plane
 * spacing of the outermost particle; the bar's extent along an axis is the
 * distance between opposite faces plus one plane spacing (30 cells of
 * 7.23 Å give 216.9 Å), so its cross-section is the area the particles
 * stand for.
 */
#ifndef CASCADE_DPD_BAR_H
#define CASCADE_DPD_BAR_H

#include <stdint.h>

#include "core/particles.h"

struct dpd_bar {
    double face_lo[3], face_hi[3];   /* Å: mean positions of the outermost planes */
    double plane;                    /* Å: (100) plane spacing, a / 2 for fcc */
    double extent[3];                /* Å: face_hi - face_lo + plane */
};

/* Measure the owned particles with no bit of `exclude` in their mask. */
void dpd_bar_measure(const struct particles *p, uint32_t exclude, double plane,
                     struct dpd_bar *bar);
/* The same over the owned particles of every rank of h (NULL: this set
 * alone, as dpd_bar_measure).  Collective when h is given. */
struct halo;
void dpd_bar_measure_over(const struct particles *p, uint32_t exclude, double plane,
                          const struct halo *h, struct dpd_bar *bar);

#endif
