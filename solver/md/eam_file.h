/*
 * eam_file: readers for the DYNAMO EAM file formats LAMMPS users have.
 *
 *   funcfl  (*.eam, pair_style eam)        one element; Z(r) with
 *           r phi(r) = 27.2 * 0.529 * Z_i(r) Z_j(r)  (Hartree*Bohr -> eV*Å)
 *   setfl   (*.eam.alloy, eam/alloy)       N elements; r phi(r) tabulated
 *   fs      (*.eam.fs, eam/fs)             N elements; density per pair
 *
 * The result is on LAMMPS's internal grid: for funcfl LAMMPS drops the last
 * point of each table (its grid has n-1 knots) and extrapolates F(rho)
 * linearly above rho_max = (nrho_file - 1) drho; for setfl and fs the file
 * grids are used as they are.
 */
#ifndef CASCADE_EAM_FILE_H
#define CASCADE_EAM_FILE_H

#include "core/particles.h"
#include "util/err.h"

enum eam_format { EAM_FUNCFL, EAM_SETFL, EAM_FS };

struct eam_data {
    enum eam_format format;
    int ne;                           /* elements */
    char element[PARTICLES_MAX_TYPES][16];
    double mass[PARTICLES_MAX_TYPES];
    int nrho, nr;                     /* knots of the internal grid */
    double drho, dr, cut, rhomax;
    int cut_line;                     /* line of the file that gives the cutoff */
    double *frho[PARTICLES_MAX_TYPES];                          /* F(rho) per element */
    double *rhor[PARTICLES_MAX_TYPES * PARTICLES_MAX_TYPES];    /* [a*ne+b]: density at a b-atom from an a-atom */
    double *z2r[PARTICLES_MAX_TYPES * PARTICLES_MAX_TYPES];     /* [a*ne+b] = r phi_ab(r), symmetric */
};

int eam_data_read(const char *path, enum eam_format fmt, struct eam_data *d, struct err *e);
void eam_data_free(struct eam_data *d);

#endif
