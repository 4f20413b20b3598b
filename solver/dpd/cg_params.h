/*
 * cg_params: the coarse-grained Sutton-Chen parameter file that DPD cases
 * reference (`dpd.parameters`), written by the MD->DPD fit (case type
 * `dpd_fit`, cg_fit.h).
 *
 * One DPD particle stands for `atoms_per_particle` atoms; its conservative
 * force is the Sutton-Chen form of core/sc_form.h with coarse-grained
 * parameters (Chen et al. 2014, Sec. 2.2: eight Cu atoms per mesoparticle,
 * coarse lattice constant 2a = 7.23 Å).  The file is YAML:
 *
 *   element: Cu               type name of the particles
 *   epsilon: 0.099            eV        (> 0)
 *   c: 39.4                   1         (> 0)
 *   n: 9                                (n > m > 0)
 *   m: 6
 *   a: 7.23                   Å         length scale of the form
 *   cutoff: 10.845            Å         shifted-force truncation
 *   mass: 508.368             amu       per particle
 *   atoms_per_particle: 8
 *   lattice_constant: 7.25    Å         fcc lattice constant at the fit's
 *                                       temperature and zero pressure
 *   fit: {...}                provenance of the fit (ignored when read)
 *
 * Errors name the parameter file, line, column and key.
 */
#ifndef CASCADE_CG_PARAMS_H
#define CASCADE_CG_PARAMS_H

#include <jansson.h>
#include <stdio.h>

#include "core/sc_form.h"
#include "util/err.h"

struct cg_params {
    char element[16];
    struct sc_params sc;       /* eps, c, n, m, a, rc (+ derived shift terms) */
    double mass;               /* amu per particle */
    long atoms_per_particle;
    double lattice_constant;   /* Å */
    char source[512];          /* the file read, for logs */
};

/* Read and validate a parameter file. */
int cg_params_load(const char *path, struct cg_params *out, struct err *e);

/* Write a parameter file; `fit` (may be NULL) is stored under `fit:` as
 * provenance.  `header` (may be NULL) becomes leading comment lines. */
int cg_params_write(const char *path, const struct cg_params *prm, const char *header,
                    const json_t *fit, struct err *e);

#endif
